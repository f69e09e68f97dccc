// The bias-free relax pass ([solver] relax_sweeps, world/parts/relax_pass.hpp): a disc sunk into
// the floor beyond the slop is pushed out by Baumgarte's bias; with the relax pass it moves as far
// as without it but keeps no separating velocity (its contact velocity ends at 0, not at the
// bias velocity); the pass reruns bit for bit; 0 sweeps is the plain step.
#include <gtest/gtest.h>

#include <array>

#include "dc/core/error.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "engine/physics_fixtures.hpp"

namespace dc {
namespace {

/// A disc at rest 20 mm into the floor (slop 5 mm, β = 0.2), after one step at `relax` sweeps
/// of the relax pass (the main solve tight).
World sunk_disc_step(int relax) {
  WorldDef d = test::one_disc({100.0, 0.98}, {0.0, 0.0}, {0.0, -9.81}, 0.5, {false, false, true, false});
  d.solver.relax_sweeps = relax;
  World w = test::world_unchecked(d);
  const auto solver = make_solver("pgs");
  w.step(*solver, test::tight_options());
  return w;
}

TEST(RelaxPass, KeepsTheBiasDisplacementButNotTheBiasVelocity) {
  const World plain = sunk_disc_step(0), relaxed = sunk_disc_step(50);
  const double dt = plain.def().time.dt;
  // Without the pass the disc leaves with the bias velocity β·(pen − slop)/Δt = 0.3 m/s …
  const double bias = 0.2 * (0.02 - 0.005) / dt;
  EXPECT_NEAR(plain.bodies().velocity[0].y, bias, 1e-9);
  // … with it the contact velocity is 0 (the disc rests on the floor, no bias, gravity held).
  EXPECT_NEAR(relaxed.bodies().velocity[0].y, 0.0, 1e-9);
  EXPECT_GE(relaxed.bodies().velocity[0].y, -1e-12);
  // Both move the disc by the bias velocity's displacement.
  EXPECT_NEAR(relaxed.bodies().position[0].y, plain.bodies().position[0].y, 1e-12);
  EXPECT_NEAR(relaxed.bodies().position[0].y - 0.98, bias * dt, 1e-9);
}

TEST(RelaxPass, RerunsBitEqual) {
  const World a = sunk_disc_step(3), b = sunk_disc_step(3);
  EXPECT_EQ(state_hash(a.bodies()), state_hash(b.bodies()));
}

TEST(RelaxPass, NegativeSweepsAreRefused) {
  WorldDef d;
  d.solver.relax_sweeps = -1;
  EXPECT_THROW(d.validate(), ConfigError);
}

}  // namespace
}  // namespace dc
