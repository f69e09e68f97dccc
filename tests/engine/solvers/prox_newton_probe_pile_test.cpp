// prox-newton's probe (ProxNewtonDef::probe_sweeps) on box-pile steps of the engine, where nncg
// plateaus: the probe's coupled passes can leave a best iterate the lead stage does not overtake
// for hundreds of sweeps. A probe that misses the target must still leave the solve as without
// it — the lead's nncg run and its stop (whose window and stall rules read the best hard
// residual), the Newton parts from the lead's best iterate (and the Newton budget's count), the
// factorisations after the probe (no kept factor of the probe's H), and the answer — apart from
// its own Newton iterations and factorisations. On unit problems the lead overtakes the probe's
// best soon (prox_newton_probe_test.cpp), so only steps like these tell whether that holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "box_pile_world.hpp"

namespace dc {
namespace {

/// A solve of `p` with checkpoints at every iteration: λ and the work so far at each.
struct PileProbeRun {
  SolveResult r;
  ProxNewtonStats st;
  std::map<int, Eigen::VectorXd> lambda;
  std::map<int, ProxNewtonStats> work;
};

PileProbeRun pile_probe_solve(const LcpProblem& p, const ProxNewtonDef& d, double tolerance) {
  SolverOptions o;
  o.max_sweeps = 10000;
  o.tolerance = tolerance;
  o.record_theta = false;
  for (int k = 1; k <= 20000; ++k) o.checkpoints.push_back(k);
  ProxNewtonSolver s(d);
  PileProbeRun out;
  o.on_checkpoint = [&out, &s](int k, const Eigen::VectorXd& lambda) {
    out.lambda[k] = lambda;
    out.work[k] = s.checkpoint_stats();
  };
  out.r = s.solve(p, {}, o);
  out.st = s.last_stats();
  return out;
}

/// The weight of the heaviest body [N] (the bench's scale of the accuracy R).
double pile_probe_scale(const LcpProblem& p, Vec2 g) {
  double heaviest = 0.0;
  for (Eigen::Index k = 0; k + 1 < p.inv_mass.size(); k += 3)
    if (p.inv_mass[k] > 0) heaviest = std::max(heaviest, 1.0 / p.inv_mass[k]);
  return std::max(1.0, heaviest * std::hypot(g.x, g.y));
}

TEST(ProxNewtonProbeOnBoxPiles, AMissedProbeLeavesTheSolveAsWithoutIt) {
  int missed = 0;
  // Three missed probes on these two piles, where the lead then plateaus for 450-1000 sweeps.
  for (const int seed : {5, 6}) {
    const WorldDef def = test::box_pile_def(seed);
    World w(def);
    test::settle_box_pile(w, 250);
    for (int step = 0; step < 2; ++step) {
      w.collide();
      const LcpProblem p = w.assemble();
      const std::string at = "seed " + std::to_string(seed) + ", step " + std::to_string(250 + step);
      ASSERT_GT(p.rows(), 0) << at;
      const double tol = 1e-6 * pile_probe_scale(p, def.world.gravity);
      const ProxNewtonDef on_def;  // the defaults: box piles count as degenerate
      ProxNewtonDef off_def;
      off_def.probe_sweeps = 0;
      const PileProbeRun on = pile_probe_solve(p, on_def, tol), off = pile_probe_solve(p, off_def, tol);
      w.integrate(off.r.lambda);
      // The probe's look: the last lead sweep before the first Newton iteration.
      int look = 0;
      while (on.work.count(look + 1) != 0 && on.work.at(look + 1).newton == 0) ++look;
      if (look == off.st.lead_sweeps) continue;  // the lead stage ended before a probe
      // The probe's passes: checkpoints look + (Newton iterations so far), one per pass.
      int n = 0;
      for (auto it = on.work.upper_bound(look); it != on.work.end() && it->second.newton == it->first - look; ++it)
        n = it->first - look;
      ASSERT_GT(n, 0) << at;
      if (on.r.sweeps == look + n) continue;  // the probe reached the target: the solve ended there
      ++missed;
      const int probe_factorizations = on.work.at(look + n).factorizations;
      ASSERT_GT(probe_factorizations, 0) << at;
      EXPECT_EQ(on.r.lambda, off.r.lambda) << at;
      EXPECT_EQ(on.r.status, off.r.status) << at;
      EXPECT_EQ(on.st.lead_sweeps, off.st.lead_sweeps) << at;
      EXPECT_EQ(on.st.finish_newton, off.st.finish_newton) << at;
      EXPECT_EQ(on.st.factorizations - off.st.factorizations, probe_factorizations) << at;
      EXPECT_EQ(on.r.sweeps - off.r.sweeps, n) << at;
      // Every iterate after the probe (the lead's later sweeps, the Newton parts) is the one
      // without it, n checkpoints later, with the probe's factorisations on top.
      for (const auto& [k, lambda] : off.lambda) {
        if (k <= look || k > off.r.sweeps) continue;  // after the probe's look, up to the final flush
        ASSERT_EQ(on.lambda.count(k + n), 1u) << at << ", checkpoint " << k;
        EXPECT_EQ(on.lambda.at(k + n), lambda) << at << ", checkpoint " << k;
        EXPECT_EQ(on.work.at(k + n).factorizations - probe_factorizations, off.work.at(k).factorizations)
            << at << ", checkpoint " << k;
        if (::testing::Test::HasFailure()) break;  // one report per step
      }
    }
  }
  EXPECT_GE(missed, 2);
}

}  // namespace
}  // namespace dc
