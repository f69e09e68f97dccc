// [bodies] internal_order = "auto" (the default): the world steps in the internal Morton order
// from internal_order_auto_min_bodies dynamic circles up, and exactly as "none" below it or
// with a shape table. Checked by bit-equal trajectories against the explicit settings.
#include <gtest/gtest.h>

#include <cstdint>

#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "world/internal_order_choice.hpp"

namespace dc {
namespace {

std::uint64_t run(WorldDef d, InternalOrder order, int steps) {
  d.bodies.internal_order = order;
  World w(d);
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 10;
  for (int s = 0; s < steps; ++s) w.step(*solver, o, World::WarmStart::PreviousLambda);
  return state_hash(w.bodies());
}

TEST(InternalOrderAuto, IsTheDefault) { EXPECT_EQ(WorldDef{}.bodies.internal_order, InternalOrder::Auto); }

TEST(InternalOrderAuto, ChoosesMortonForLargeCirclePilesOnly) {
  BodyState circles;
  for (int k = 0; k < internal_order_auto_min_bodies; ++k) circles.add({2.0 * k, 1.0}, 1.0, 1.0);
  EXPECT_TRUE(steps_in_internal_order(InternalOrder::Auto, circles));
  EXPECT_TRUE(steps_in_internal_order(InternalOrder::Morton, circles));
  EXPECT_FALSE(steps_in_internal_order(InternalOrder::None, circles));
  BodyState fewer;
  for (int k = 0; k + 1 < internal_order_auto_min_bodies; ++k) fewer.add({2.0 * k, 1.0}, 1.0, 1.0);
  EXPECT_FALSE(steps_in_internal_order(InternalOrder::Auto, fewer));
  EXPECT_TRUE(steps_in_internal_order(InternalOrder::Morton, fewer));
  BodyState shaped = circles;
  shaped.add_shaped(make_box({1.0, 1.0}, "test"), Motion::Static, {1.0, 1.0}, 1.0);
  EXPECT_FALSE(steps_in_internal_order(InternalOrder::Auto, shaped));
}

TEST(InternalOrderAuto, StepsAsNoneBelowTheThresholdAndAsMortonFromIt) {
  WorldDef small = stress::scaled_seed_pile(internal_order_auto_min_bodies - 1);
  WorldDef large = stress::scaled_seed_pile(internal_order_auto_min_bodies);
  // A world in the internal order sorts it when built; one without never does.
  EXPECT_EQ(World(small).internal_order_resorts(), 0);
  EXPECT_EQ(World(large).internal_order_resorts(), 1);
  // Bodies low in the box: the piles' first steps have contacts.
  small.bodies.mean.y = large.bodies.mean.y = 0.3 * large.world.height;
  EXPECT_EQ(run(small, InternalOrder::Auto, 3), run(small, InternalOrder::None, 3));
  EXPECT_EQ(run(large, InternalOrder::Auto, 3), run(large, InternalOrder::Morton, 3));
}

}  // namespace
}  // namespace dc
