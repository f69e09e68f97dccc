// prox-newton's drift jumps (ProxNewtonDef::degenerate_drift_jumps) on box-pile steps of the
// engine, where nncg's plateaus are drifts along A's null space: a jump changes nothing where
// none is made, the caller's checkpoints count on across a jump's new nncg run, and where jumps
// are made the solve reaches the accuracy R in fewer iterations than without them, over these
// steps together.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "box_pile_world.hpp"

namespace dc {
namespace {

struct DriftPileRun {
  SolveResult r;
  ProxNewtonStats st;
  int to_r = -1;  // the first checkpoint whose λ is at R (-1: never)
  int last_k = 0;
  bool counted_on = true;  // every checkpoint after the one before (a jump's new nncg run included)
};

DriftPileRun drift_pile_solve(const LcpProblem& p, int jumps, double r_n) {
  ProxNewtonDef d;
  d.degenerate_drift_jumps = jumps;
  ProxNewtonSolver s(d);
  SolverOptions o;
  o.max_sweeps = 10000;
  o.tolerance = r_n;
  o.record_theta = false;
  for (int k = 1; k <= 20000; ++k) o.checkpoints.push_back(k);
  DriftPileRun out;
  o.on_checkpoint = [&out, &p, r_n](int k, const Eigen::VectorXd& lambda) {
    out.counted_on = out.counted_on && k > out.last_k;
    out.last_k = k;
    if (out.to_r < 0 && natural_residual(p, lambda) <= r_n) out.to_r = k;
  };
  out.r = s.solve(p, {}, o);
  out.st = s.last_stats();
  return out;
}

TEST(ProxNewtonDriftOnBoxPiles, JumpsChangeNothingUnlessMadeAndReachRSoonerWhereMade) {
  int jumped_steps = 0, with_jumps = 0, without_jumps = 0;
  for (const int seed : {5, 6}) {
    const WorldDef def = test::box_pile_def(seed);
    World w(def);
    test::settle_box_pile(w, 250);
    for (int step = 0; step < 3; ++step) {
      w.collide();
      const LcpProblem p = w.assemble();
      const std::string at = "seed " + std::to_string(seed) + ", step " + std::to_string(250 + step);
      ASSERT_GT(p.rows(), 0) << at;
      double heaviest = 0.0;
      for (Eigen::Index k = 0; k + 1 < p.inv_mass.size(); k += 3)
        if (p.inv_mass[k] > 0) heaviest = std::max(heaviest, 1.0 / p.inv_mass[k]);
      const double r_n = 1e-6 * heaviest * std::hypot(def.world.gravity.x, def.world.gravity.y);
      const DriftPileRun on = drift_pile_solve(p, 16, r_n), off = drift_pile_solve(p, 0, r_n);
      w.integrate(off.r.lambda);
      EXPECT_EQ(off.st.drift_jumps, 0) << at;
      if (on.st.drift_jumps == 0) {
        EXPECT_EQ(on.r.lambda, off.r.lambda) << at;
        EXPECT_EQ(on.st.lead_sweeps, off.st.lead_sweeps) << at;
        continue;
      }
      ++jumped_steps;
      EXPECT_TRUE(on.counted_on) << at;
      ASSERT_GT(on.to_r, 0) << at << ": " << on.r.message;
      ASSERT_GT(off.to_r, 0) << at << ": " << off.r.message;
      with_jumps += on.to_r;
      without_jumps += off.to_r;
    }
  }
  ASSERT_GE(jumped_steps, 2);
  EXPECT_LT(with_jumps, without_jumps);
}

}  // namespace
}  // namespace dc
