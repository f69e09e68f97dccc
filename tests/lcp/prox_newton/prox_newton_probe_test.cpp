// prox-newton's probe (ProxNewtonDef::probe_sweeps, probe_iterations): on degenerate problems,
// coupled body-space passes from the best iterate at one look of the lead stage. A probe that
// reaches the target ends the solve there; one that misses leaves the solve as without it (the
// same λ, the lead's nncg run untouched) apart from its Newton iterations; problems below
// degenerate_rows get none.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <map>
#include <vector>
#include <string>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/prox_newton/probe_trace.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

struct Outcome {
  SolveResult r;
  ProxNewtonStats st;
};

Outcome solve(const LcpProblem& p, const ProxNewtonDef& d, double tolerance) {
  SolverOptions o;
  o.max_sweeps = 500;
  o.tolerance = tolerance;
  ProxNewtonSolver s(d);
  Outcome out;
  out.r = s.solve(p, {}, o);
  out.st = s.last_stats();
  return out;
}

/// A resting pile with friction, and settings that count it as degenerate (its rows per
/// velocity unknown are above 1) with a probe at the first look (50 sweeps), whatever the best
/// hard residual there (probe_reach = 0).
struct Pile {
  LcpProblem p = test::deep_pile(12, 6, 0.9);
  ProxNewtonDef def;
  double scale = std::max(1.0, p.b.cwiseAbs().maxCoeff());
  Pile() {
    def.degenerate_rows = 0.99 * static_cast<double>(p.rows()) / static_cast<double>(p.J.cols());
    def.probe_sweeps = 50;
    def.probe_reach = 0;
  }
  [[nodiscard]] ProxNewtonDef without_probe() const {
    ProxNewtonDef d = def;
    d.probe_sweeps = 0;
    return d;
  }
};

TEST(ProxNewtonProbe, AProbeAtTheTargetEndsTheSolve) {
  // Random contact problems with 1.33 rows per velocity unknown (degenerate by default) and a
  // target nncg reaches after more sweeps than the probe's, the default settings otherwise.
  int ended = 0;  // solves the probe ended
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 3400);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    ProxNewtonDef def;
    def.degenerate_drift_jumps = 0;  // the jumps bring nncg there before the probe on these problems
    def.probe_reach = 0;
    ASSERT_GE(static_cast<double>(p.rows()), def.degenerate_rows * static_cast<double>(p.J.cols()));
    const double tol = 1e-6 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
    ProxNewtonDef no_probe = def;
    no_probe.probe_sweeps = 0;
    const Outcome off = solve(p, no_probe, tol);
    if (off.st.lead_sweeps <= def.probe_sweeps) continue;  // nncg alone is there before the probe
    const Outcome on = solve(p, def, tol);
    // The shared status rule: at the tolerance, and Converged only when the solution test holds.
    EXPECT_TRUE(on.r.status == SolveStatus::Converged || on.r.status == SolveStatus::ToleranceReached) << seed;
    EXPECT_LE(natural_residual(p, on.r.lambda), tol) << seed;
    if (on.st.lead_sweeps != def.probe_sweeps) continue;  // the probe missed: nncg went on
    ++ended;
    EXPECT_GT(on.st.newton, 0) << seed;
    EXPECT_LE(on.st.newton, def.probe_iterations) << seed;
    EXPECT_EQ(on.st.finish_newton, 0) << seed;
    EXPECT_EQ(on.r.message.rfind("finished by prox:", 0), 0u) << on.r.message;
  }
  EXPECT_GE(ended, 1);
}

/// A probe with `def`'s settings that misses `tol` leaves the solve of p as without it; false
/// when the probe reached the target instead.
bool missed_as_without(const LcpProblem& p, ProxNewtonDef def, double tol, const std::string& at) {
  const Outcome on = solve(p, def, tol);
  def.probe_sweeps = 0;
  const Outcome off = solve(p, def, tol);
  if (on.st.lead_sweeps <= off.st.lead_sweeps && on.st.lead_sweeps < off.st.lead_sweeps) return false;
  EXPECT_EQ(on.r.status, off.r.status) << at;
  EXPECT_EQ(on.r.lambda, off.r.lambda) << at;
  EXPECT_EQ(on.st.lead_sweeps, off.st.lead_sweeps) << at;
  EXPECT_EQ(on.st.finish_newton, off.st.finish_newton) << at;
  EXPECT_LE(on.st.newton - off.st.newton, def.probe_iterations) << at;
  // Its iterations count among the solve's (SolveResult::sweeps: lead sweeps, then Newton).
  EXPECT_EQ(on.r.sweeps - off.r.sweeps, on.st.newton - off.st.newton) << at;
  return true;
}

TEST(ProxNewtonProbe, AMissedProbeLeavesTheSolveAsWithoutIt) {
  // Probes of 1–3 iterations far from a tight target: on the pile at 50 or 100 sweeps, on
  // random contact problems (degenerate by default) at the default probe_sweeps.
  Pile pile;
  int missed = 0;
  for (const int sweeps : {50, 100})
    for (int iterations = 1; iterations <= 3; ++iterations) {
      pile.def.probe_sweeps = sweeps;
      pile.def.probe_iterations = iterations;
      missed += missed_as_without(pile.p, pile.def, 1e-10 * pile.scale,
                                  "pile " + std::to_string(sweeps) + " sweeps, " + std::to_string(iterations) + " iterations");
    }
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 3400);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    for (int iterations = 1; iterations <= 3; ++iterations)
      for (const double shift : {1e-2, 1e-4}) {  // a smaller δ: a probe iterate nearer the solution
        ProxNewtonDef d;
        d.probe_iterations = iterations;
        d.initial_shift = shift;
        d.probe_reach = 0;  // a probe at probe_sweeps however far from the tight target
        missed += missed_as_without(p, d, 1e-12 * std::max(1.0, p.b.cwiseAbs().maxCoeff()),
                                    "seed " + std::to_string(seed) + ", " + std::to_string(iterations) + " iterations");
      }
  }
  EXPECT_GE(missed, 6);
}

/// λ at every checkpoint (every iteration) of a solve.
std::map<int, Eigen::VectorXd> checkpoints(const LcpProblem& p, const ProxNewtonDef& d, double tolerance) {
  SolverOptions o;
  o.max_sweeps = 500;
  o.tolerance = tolerance;
  for (int k = 1; k <= 3000; ++k) o.checkpoints.push_back(k);
  std::map<int, Eigen::VectorXd> seen;
  o.on_checkpoint = [&seen](int k, const Eigen::VectorXd& lambda) { seen[k] = lambda; };
  ProxNewtonSolver s(d);
  (void)s.solve(p, {}, o);
  return seen;
}

TEST(ProxNewtonProbe, TheLeadsLaterSweepsFollowTheProbesIterationsInTheCheckpoints) {
  Pile pile;
  pile.def.probe_iterations = 1;
  const double tol = 1e-10 * pile.scale;
  const auto off = checkpoints(pile.p, pile.without_probe(), tol);
  const auto on = checkpoints(pile.p, pile.def, tol);
  const int n = pile.def.probe_iterations;  // the missed probe's Newton iterations
  // Up to the probe's look the same sweeps; the lead's sweep k after it comes n checkpoints later.
  for (int k = 1; k <= pile.def.probe_sweeps; ++k) EXPECT_EQ(on.at(k), off.at(k)) << k;
  for (int k = pile.def.probe_sweeps + 1; k <= pile.def.probe_sweeps + 40; ++k) EXPECT_EQ(on.at(k + n), off.at(k)) << k;
}

TEST(ProxNewtonProbe, AProbeWaitsForALookWithinReachOfTheTarget) {
  // probe_reach: the probe runs at the first look at or after probe_sweeps whose best hard
  // residual is within probe_reach × the target, not at an earlier one.
  Pile pile;
  pile.def.degenerate_drift_jumps = 0;  // looks at the lead's own iterates
  pile.def.probe_iterations = 1;
  const double tol = 1e-10 * pile.scale;
  const test::ProbeTrace first = test::probe_trace(pile.p, pile.def, tol, 500);  // probe_reach 0: at the first look
  ASSERT_FALSE(first.probes.empty());
  ASSERT_EQ(first.probes.front(), pile.def.probe_sweeps);
  const test::ProbeTrace off = test::probe_trace(pile.p, pile.without_probe(), tol, 500);
  ASSERT_GE(off.best.size(), 4u);
  // A reach between the best at the first look and at a later one that fell 10-fold below it.
  size_t later = 1;
  while (later < off.best.size() && off.best[later] * 10 > off.best[0]) ++later;
  ASSERT_LT(later, off.best.size()) << "the lead's best does not fall 10-fold";
  ProxNewtonDef def = pile.def;
  def.probe_reach = std::sqrt(off.best[0] * off.best[later]) / tol;
  size_t expected = 0;
  while (off.best[expected] > def.probe_reach * tol) ++expected;
  ASSERT_GT(expected, 0u);
  const test::ProbeTrace on = test::probe_trace(pile.p, def, tol, 500);
  ASSERT_FALSE(on.probes.empty());
  EXPECT_EQ(on.probes.front(), 50 * static_cast<int>(expected + 1));
  // Up to there the lead's looks saw what they see without the probe.
  for (size_t j = 0; j <= expected && j < on.best.size(); ++j) EXPECT_EQ(on.best[j], off.best[j]) << j;
}

TEST(ProxNewtonProbe, NoProbeBelowTheDegenerateRatio) {
  Pile pile;
  pile.def.degenerate_rows = 1e9;
  const double tol = 1e-6 * pile.scale;
  const Outcome off = solve(pile.p, pile.without_probe(), tol);
  const Outcome on = solve(pile.p, pile.def, tol);
  EXPECT_EQ(on.r.lambda, off.r.lambda);
  EXPECT_EQ(on.st.lead_sweeps, off.st.lead_sweeps);
  EXPECT_EQ(on.st.newton, off.st.newton);
}

TEST(ProxNewtonProbe, RefusesInvalidSettings) {
  ProxNewtonDef d;
  d.probe_sweeps = -1;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
  d = {};
  d.probe_iterations = -1;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
  d = {};
  d.probe_reach = -1;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
}

}  // namespace
}  // namespace dc
