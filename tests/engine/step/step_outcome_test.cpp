// The step outcome the bench reads (penetration and energy a candidate λ would produce,
// World::predict) equals what integrating the world with that λ really does: energy from
// World's own diagnostics after World::integrate, gaps recomputed here from the integrated
// centres and the box walls (independently of the narrow phase).
#include <gtest/gtest.h>

#include <algorithm>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/engine/step_outcome.hpp"

namespace dc {
namespace {

/// New gap of contact c from the integrated state (walls: the box planes of `d`).
double gap_after(const Contact& c, const BodyState& s, const WorldDef& d) {
  const auto b = static_cast<std::size_t>(c.body_b);
  const Vec2 x = s.position[b];
  const double r = s.radius[b];
  switch (c.body_a) {
    case static_cast<int>(Wall::Left): return x.x - r;
    case static_cast<int>(Wall::Right): return d.world.width - x.x - r;
    case static_cast<int>(Wall::Bottom): return x.y - r;
    case static_cast<int>(Wall::Top): return d.world.height - x.y - r;
    default: break;
  }
  const auto a = static_cast<std::size_t>(c.body_a);
  return length(x - s.position[a]) - r - s.radius[a];
}

TEST(StepOutcome, EqualsTheIntegratedWorld) {
  WorldDef d;
  d.bodies.count = 30;
  d.bodies.mean = {15.0, 5.0};
  d.bodies.sigma = 3.0;
  d.world.gravity = {1.5, -9.81};  // both components of gravity enter the outcome
  World w(d);
  const auto pgs = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 30;
  for (int s = 0; s < 80; ++s) w.step(*pgs, o);
  w.collide();
  const LcpProblem& p = w.assemble();
  ASSERT_GT(p.rows(), 20);
  // A loose λ (few sweeps) and zero: both leave some penetration, with different energies.
  o.max_sweeps = 5;
  const Eigen::VectorXd loose = pgs->solve(p, Eigen::VectorXd::Zero(p.rows()), o).lambda;
  for (const Eigen::VectorXd& lambda : {loose, Eigen::VectorXd::Zero(p.rows()).eval()}) {
    StepOutcome out;
    w.predict(lambda, out);
    World after = w;
    after.integrate(lambda);
    const double energy = after.kinetic_energy() + after.potential_energy();
    EXPECT_NEAR(out.energy(), energy, 1e-9 * std::abs(energy));
    double min_gap = 0;
    for (const Contact& c : w.contacts()) min_gap = std::min(min_gap, gap_after(c, after.bodies(), d));
    EXPECT_NEAR(out.max_penetration(), -min_gap, 1e-12);
  }
}

}  // namespace
}  // namespace dc
