// prox-newton's later probes (ProxNewtonDef::probe_count, probe_refall, probe_shift): after a
// missed probe, another runs only at a look whose best hard residual fell probe_refall-fold
// below the best where the last one started; missed probes leave the solve's answer as without
// them; probe_shift sets the probe's first δ alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/prox_newton/probe_trace.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

/// A resting pile with friction counted as degenerate, the probe from the first look on
/// (probe_sweeps 50, probe_reach 0: whatever the best there) and one Newton iteration a probe,
/// so that against a tight target every probe misses and the lead's run goes on.
struct ProbeCountPile {
  LcpProblem p = test::deep_pile(12, 6, 0.9);
  ProxNewtonDef def;
  double tol = 1e-10 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
  ProbeCountPile() {
    def.degenerate_rows = 0.99 * static_cast<double>(p.rows()) / static_cast<double>(p.J.cols());
    def.degenerate_drift_jumps = 0;  // the lead's looks at its own iterates
    def.probe_sweeps = 50;
    def.probe_reach = 0;
    def.probe_iterations = 1;
  }
};

TEST(ProxNewtonProbeCount, ALaterProbeWaitsForTheRefallOfTheBest) {
  ProbeCountPile pile;
  pile.def.probe_count = 3;
  pile.def.probe_refall = 4;
  ProxNewtonDef off = pile.def;
  off.probe_sweeps = 0;
  const test::ProbeTrace without = test::probe_trace(pile.p, off, pile.tol, 1000);
  const test::ProbeTrace with = test::probe_trace(pile.p, pile.def, pile.tol, 1000);
  ASSERT_TRUE(without.probes.empty());
  ASSERT_GE(with.probes.size(), 2u) << "the lead's best does not fall 4-fold twice";
  // The first probe at the first look; each later one at the first look whose best fell
  // probe_refall-fold below the best where the one before it ran (the lead's looks are
  // the same as without the probes: a missed probe leaves the lead's run untouched).
  EXPECT_EQ(with.probes[0], 50);
  for (size_t i = 1; i < with.probes.size(); ++i) {
    const size_t before = static_cast<size_t>(with.probes[i - 1] / 50 - 1);
    size_t expected = before + 1;
    while (expected < without.best.size() && without.best[expected] * pile.def.probe_refall > without.best[before])
      ++expected;
    EXPECT_EQ(with.probes[i], 50 * static_cast<int>(expected + 1)) << "probe " << i;
  }
  EXPECT_LE(static_cast<int>(with.probes.size()), pile.def.probe_count);
  for (size_t j = 0; j < std::min(with.best.size(), without.best.size()); ++j)
    EXPECT_EQ(with.best[j], without.best[j]) << "look " << j + 1;
}

TEST(ProxNewtonProbeCount, MissedProbesLeaveTheAnswerAsWithoutThem) {
  ProbeCountPile pile;
  ProxNewtonDef off = pile.def;
  off.probe_sweeps = 0;
  SolverOptions o;
  o.max_sweeps = 1000;
  o.tolerance = pile.tol;
  ProxNewtonSolver without(off);
  const SolveResult r0 = without.solve(pile.p, {}, o);
  int probes_seen = 0;
  for (const int count : {1, 2, 4}) {
    ProxNewtonDef d = pile.def;
    d.probe_count = count;
    d.probe_refall = 2;
    ProxNewtonSolver with(d);
    const SolveResult r = with.solve(pile.p, {}, o);
    if (r.lambda == r0.lambda) {
      EXPECT_EQ(with.last_stats().lead_sweeps, without.last_stats().lead_sweeps) << count;
      EXPECT_LE(with.last_stats().newton - without.last_stats().newton, count * d.probe_iterations) << count;
      probes_seen = std::max(probes_seen, with.last_stats().newton - without.last_stats().newton);
    } else {
      // A probe's best iterate is a candidate for the answer: never a worse one.
      EXPECT_LE(natural_residual(pile.p, r.lambda), natural_residual(pile.p, r0.lambda)) << count;
    }
  }
  EXPECT_GE(probes_seen, 2);
}

TEST(ProxNewtonProbeCount, ProbeShiftIsTheProbesFirstShiftAlone) {
  // probe_shift = 0 takes initial_shift: the same solve as probe_shift = initial_shift. Another
  // probe_shift changes the probe's passes (and the solve where a probe ran), and initial_shift
  // does not reach the probe once probe_shift is set.
  int changed = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 3400);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    SolverOptions o;
    o.max_sweeps = 1000;
    o.tolerance = 1e-6 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
    ProxNewtonDef zero;
    zero.degenerate_drift_jumps = 0;  // the jumps bring nncg there before the probe on these problems
    zero.probe_reach = 0;
    zero.probe_shift = 0;
    ProxNewtonDef same = zero;
    same.probe_shift = zero.initial_shift;
    ProxNewtonSolver a(zero), b(same);
    const SolveResult ra = a.solve(p, {}, o);
    EXPECT_EQ(ra.lambda, b.solve(p, {}, o).lambda) << seed;
    EXPECT_EQ(a.last_stats().newton, b.last_stats().newton) << seed;
    if (a.last_stats().newton == 0) continue;  // no probe, no Newton part: nothing to tell apart
    ProxNewtonDef other = zero;
    other.probe_shift = zero.initial_shift / 100;
    ProxNewtonSolver c(other);
    const SolveResult rc = c.solve(p, {}, o);
    changed += rc.lambda != ra.lambda ? 1 : 0;
    // Every iterate is still judged by the hard residual: the answer at the tolerance.
    EXPECT_LE(natural_residual(p, rc.lambda), o.tolerance) << seed;
  }
  EXPECT_GE(changed, 1);
}

TEST(ProxNewtonProbeCount, RefusesInvalidSettings) {
  ProxNewtonDef d;
  d.probe_count = -1;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
  d = {};
  d.probe_refall = 0.5;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
  d = {};
  d.probe_shift = -1;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
}

}  // namespace
}  // namespace dc
