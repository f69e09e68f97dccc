// Bodies added during a run (inflow.hpp): the [inflow] emission count and placement, late
// [[body]] spawns, stable indices, determinism; and the [bodies] region / radius_max keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"

namespace dc {
namespace {

WorldDef pour(double rate = 100, double stop = 0.5) {
  WorldDef d;
  d.bodies.count = 0;
  d.world.width = 20;
  d.world.height = 30;
  d.inflow.rate = rate;
  d.inflow.region = {1, 20, 19, 29};
  d.inflow.start = 0.1;
  d.inflow.stop = stop;
  d.inflow.velocity = {0.0, -5.0};
  d.inflow.radius = 0.5;
  return d;
}

void expect_no_overlap(const BodyState& s) {
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j)
      ASSERT_GE(length(s.position[i] - s.position[j]), s.radius[i] + s.radius[j]) << i << " " << j;
}

TEST(Inflow, EmitsRateTimesElapsedTimeInTheRegionWithoutOverlap) {
  World w(pour());
  EXPECT_EQ(w.bodies().size(), 0u);  // start = 0.1 s
  const auto pgs = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 50;
  std::size_t before = 0;
  for (int s = 1; s <= 60; ++s) {
    const BodyState old = w.bodies();
    w.step(*pgs, o);
    const double t = w.time();
    // Emission times 0.1 + k/100 ≤ t and < 0.5: floor((t − 0.1)·100) + 1, at most 40 (the
    // region never fills at this rate: every body finds a spot at once).
    const std::size_t expect = t < 0.1 - 1e-12 ? 0 : std::min<std::size_t>(40, static_cast<std::size_t>(std::floor((t - 0.1) * 100 + 1e-9)) + 1);
    ASSERT_EQ(w.bodies().size(), expect) << "step " << s;
    // New bodies are appended: the old ones keep their indices (and radii); new ones are
    // inside the region with the inflow velocity.
    for (std::size_t k = 0; k < old.size(); ++k) ASSERT_EQ(w.bodies().radius[k], old.radius[k]);
    for (std::size_t k = before; k < w.bodies().size(); ++k) {
      const Vec2 x = w.bodies().position[k];
      EXPECT_GE(x.x, 1.0); EXPECT_LE(x.x, 19.0); EXPECT_GE(x.y, 20.0); EXPECT_LE(x.y, 29.0);
      EXPECT_EQ(w.bodies().velocity[k].y, -5.0);
    }
    before = w.bodies().size();
    expect_no_overlap(w.bodies());
  }
  EXPECT_EQ(w.inflow().total(), 40);
  EXPECT_FALSE(w.inflow().pending());
}

TEST(Inflow, IsSeededByTheSceneSeedAndDeterministic) {
  const auto run = [](std::uint64_t seed) {
    WorldDef d = pour();
    d.bodies.seed = seed;
    World w(d);
    const auto pgs = make_solver("pgs");
    SolverOptions o;
    o.max_sweeps = 30;
    for (int s = 0; s < 30; ++s) w.step(*pgs, o);
    return state_hash(w.bodies());
  };
  EXPECT_EQ(run(3), run(3));
  EXPECT_NE(run(3), run(4));
}

TEST(Inflow, AFullRegionMakesBodiesWaitInsteadOfOverlapping) {
  WorldDef d = pour(1000, 1.0);  // 10 per step into a region that holds few
  d.inflow.region = {9, 27, 11, 29};
  d.inflow.velocity = {0, 0};
  d.world.gravity = {0, 0};      // nothing leaves the region
  World w(d);
  const auto pgs = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 20;
  for (int s = 0; s < 20; ++s) w.step(*pgs, o);
  EXPECT_LT(w.inflow().added(), 12);
  EXPECT_TRUE(w.inflow().pending());
  expect_no_overlap(w.bodies());
}

TEST(Inflow, LateBodyEntersAtItsSpawnTimeAsTheLastIndex) {
  WorldDef d;
  d.bodies.count = 5;
  d.bodies.mean = {15, 5};
  d.bodies.sigma = 2;
  BodyDef heavy;
  heavy.position = {15, 25};
  heavy.velocity = {0, -10};
  heavy.radius = 1.5;
  heavy.density = 20;
  heavy.spawn = 0.05;
  d.body.push_back(heavy);
  World w(d);
  EXPECT_EQ(w.bodies().size(), 5u);
  const auto pgs = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 50;
  for (int s = 0; s < 4; ++s) w.step(*pgs, o);
  EXPECT_EQ(w.bodies().size(), 5u);  // t = 0.04
  w.step(*pgs, o);                   // t = 0.05
  ASSERT_EQ(w.bodies().size(), 6u);
  EXPECT_EQ(w.bodies().radius[5], 1.5);
  EXPECT_EQ(w.bodies().velocity[5].y, -10.0);
  EXPECT_EQ(w.bodies().position[5].y, 25.0);
}

TEST(Inflow, CircleScenesDrawNoExtraNumbers) {
  // The same generated circles with and without the new keys at their defaults.
  WorldDef a;
  WorldDef b;
  b.inflow.radius = 0.7;  // inactive inflow: no effect
  EXPECT_EQ(state_hash(World(a).bodies()), state_hash(World(b).bodies()));
}

TEST(BodiesRegion, UniformPlacementInsideTheRegionAndRadiusSpread) {
  WorldDef d;
  d.world.width = 12;
  d.world.height = 150;
  d.bodies.count = 400;
  d.bodies.radius = 0.3;
  d.bodies.radius_max = 0.9;
  d.bodies.region = {0, 0, 12, 100};
  World w(d);
  const BodyState& s = w.bodies();
  ASSERT_EQ(s.size(), 400u);
  double rmin = 1e9, rmax = 0, ymax = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    rmin = std::min(rmin, s.radius[k]);
    rmax = std::max(rmax, s.radius[k]);
    ymax = std::max(ymax, s.position[k].y);
    EXPECT_NEAR(s.mass[k], std::numbers::pi * s.radius[k] * s.radius[k], 1e-12);
  }
  EXPECT_GE(rmin, 0.3);
  EXPECT_LT(rmax, 0.9);
  EXPECT_GT(rmax / rmin, 2.5);  // spread over (nearly) the factor 3
  EXPECT_LE(ymax, 100.0);
  EXPECT_GT(ymax, 80.0);         // uniform in the region, not a Gaussian around (15, 15)
  expect_no_overlap(s);
}

TEST(InflowKeys, ParseValidateAndRoundTrip) {
  const WorldDef d = parse_scene(R"([bodies]
count = 0
region = [0.0, 0.0, 10.0, 10.0]
[inflow]
rate = 50
region = [1, 20, 9, 28]
start = 0.5
stop = 2
velocity = [0.5, -1]
radius = 0.4
radius_max = 0.8
[[body]]
position = [5.0, 5.0]
spawn = 1.5
)", "t.toml");
  EXPECT_EQ(d.inflow.rate, 50);
  EXPECT_EQ(d.inflow.region[3], 28);
  EXPECT_EQ(d.inflow.velocity.x, 0.5);
  EXPECT_EQ(d.body[0].spawn, 1.5);
  EXPECT_EQ(parse_scene(scene_to_toml(d), "back.toml"), d);
  EXPECT_THROW(parse_scene("[inflow]\nrate = 5\n", "t.toml"), ConfigError);  // no region
  EXPECT_THROW(parse_scene("[inflow]\nrate = 5\nregion = [0, 0, 1, 1]\nstart = 1\nstop = 1\n", "t.toml"), ConfigError);
  EXPECT_THROW(parse_scene("[bodies]\nregion = [0, 0, 1]\n", "t.toml"), ConfigError);
  EXPECT_THROW(parse_scene("[bodies]\nradius_max = 0.5\n", "t.toml"), ConfigError);  // < radius 1
}

}  // namespace
}  // namespace dc
