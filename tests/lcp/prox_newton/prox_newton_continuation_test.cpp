// prox-newton's continuation in μ (solvers/prox_newton/finish/mu_continuation.hpp): the problem
// with μ scaled, the stage fractions, the finish reaching the hard target of the problem itself
// when the other parts are cut short, and no continuation where the parts reach the target.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <limits>
#include <string>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/finish/mu_continuation.hpp"

namespace dc {
namespace {

using solvers::prox::continuation_fraction;
using solvers::prox::with_scaled_friction;

/// Every part but the continuation cut to the lead stage's nncg sweeps (options.max_sweeps) and
/// one frozen pass of one Newton iteration.
ProxNewtonDef continuation_cut_def() {
  ProxNewtonDef d;
  d.max_outer = 1;
  d.body_inner_iterations = 1;
  d.inner_iterations = 1;
  d.finish_iterations = 0;
  d.proximal_finish = false;
  d.safeguard_sweeps = 0;
  d.pivot_rows = 0;
  d.local_pivot_rows = 0;
  d.continuation_within = std::numeric_limits<double>::infinity();  // however far the cut parts end
  return d;
}

TEST(ProxNewtonContinuation, ScalesEveryFrictionCoefficientAndNothingElse) {
  test::TestRng rng(4101);
  const LcpProblem p = test::random_contact(10, 24, true, rng, 0.6, 3);  // every 3rd frictionless
  const LcpProblem q = with_scaled_friction(p, 0.25);
  ASSERT_EQ(q.rows(), p.rows());
  for (int i = 0; i < p.rows(); ++i) {
    EXPECT_EQ(q.mu[i], p.is_friction_row(i) ? 0.25 * p.mu[i] : p.mu[i]) << "row " << i;
    EXPECT_EQ(q.b[i], p.b[i]);
    EXPECT_EQ(q.lo[i], p.lo[i]);
    EXPECT_EQ(q.hi[i], p.hi[i]);
    EXPECT_EQ(q.normal_row[static_cast<size_t>(i)], p.normal_row[static_cast<size_t>(i)]);
  }
  ASSERT_EQ(q.constraints.size(), p.constraints.size());
  for (int c = 0; c < p.constraints.size(); ++c) {
    EXPECT_EQ(q.constraints[c].mu, 0.25 * p.constraints[c].mu) << "contact " << c;
    EXPECT_EQ(q.constraints[c].tangent_row, p.constraints[c].tangent_row);
  }
  // A valid problem: the solver takes it (its input checks compare rows and contacts).
  const SolveResult r = ProxNewtonSolver().solve(q, {}, test::capped_options());
  EXPECT_EQ(r.status, SolveStatus::Converged) << r.message;
  EXPECT_THROW((void)with_scaled_friction(p, 0.0), InvalidArgument);
  EXPECT_THROW((void)with_scaled_friction(p, 1.5), InvalidArgument);
}

TEST(ProxNewtonContinuation, StageFractionsHalveTheGapToOne) {
  EXPECT_DOUBLE_EQ(continuation_fraction(0.25, 0), 0.25);
  EXPECT_DOUBLE_EQ(continuation_fraction(0.25, 1), 0.625);
  EXPECT_DOUBLE_EQ(continuation_fraction(0.25, 2), 0.8125);
  EXPECT_LT(continuation_fraction(0.25, 6), 1.0);
  ProxNewtonDef bad;
  bad.continuation_first = 1.0;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
  bad.continuation_first = 0.25;
  bad.continuation_stages = -1;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
}

// Every stage reaches its target on a pile the default parts solve, and the last solve is of
// the problem itself: its answer meets the hard target of the unscaled problem.
TEST(ProxNewtonContinuation, ItsLastSolveIsOfTheProblemItself) {
  const ProxNewtonDef def;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 4200);
    const LcpProblem c = test::random_contact(20, 60, true, rng, 0.8);
    const double target = 1e-7 * std::max(1.0, c.b.lpNorm<Eigen::Infinity>());
    const solvers::prox::ContinuationOutcome co =
        solvers::prox::continuation_solve(c, Eigen::VectorXd::Zero(c.rows()), def, target, 300);
    EXPECT_EQ(co.solves, def.continuation_stages + 1) << "seed " << seed;
    EXPECT_LE(natural_residual(c, co.lambda), target) << "seed " << seed;
  }
}

// The cut parts miss the target: the continuation runs, and its answer is kept only when it is
// better than theirs.
TEST(ProxNewtonContinuation, RunsWhereThePartsMissTheTarget) {
  const ProxNewtonDef with = continuation_cut_def();
  ProxNewtonDef without = with;
  without.continuation_stages = 0;
  int missed = 0;
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    test::TestRng rng(seed + 4200);
    const LcpProblem c = test::random_contact(20, 60, true, rng, 0.8);
    const SolveResult cut = ProxNewtonSolver(without).solve(c, {}, test::capped_options());
    if (cut.status == SolveStatus::Converged) continue;  // too easy for the cut parts
    ++missed;
    ProxNewtonSolver s(with);
    const SolveResult r = s.solve(c, {}, test::capped_options());
    EXPECT_GE(s.last_stats().continuation_solves, 1) << "seed " << seed;
    EXPECT_NE(r.message.find("continuation solves"), std::string::npos) << r.message;
    EXPECT_LE(natural_residual(c, r.lambda), natural_residual(c, cut.lambda)) << "seed " << seed;
  }
  EXPECT_GE(missed, 2);
}

// The continuation is for near misses: where the parts end farther above the target than
// continuation_within times it, it does not run (continuation_within = 1: never).
TEST(ProxNewtonContinuation, DoesNotRunWhereThePartsEndFarAboveTheTarget) {
  ProxNewtonDef near = continuation_cut_def();
  near.continuation_within = 1.0;
  int missed = 0;
  for (uint64_t seed = 1; seed <= 8; ++seed) {
    test::TestRng rng(seed + 4200);
    const LcpProblem c = test::random_contact(20, 60, true, rng, 0.8);
    ProxNewtonSolver s(near);
    const SolveResult r = s.solve(c, {}, test::capped_options());
    if (r.status == SolveStatus::Converged) continue;
    ++missed;
    EXPECT_EQ(s.last_stats().continuation_solves, 0) << "seed " << seed;
  }
  EXPECT_GE(missed, 2);
  ProxNewtonDef bad;
  bad.continuation_within = 0.5;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
}

// A stage that misses its target ends the continuation: one solve where the first stage's
// cannot reach it (one iteration), not a solve per stage.
TEST(ProxNewtonContinuation, EndsAtTheFirstStageThatMissesItsTarget) {
  test::TestRng rng(4401);
  const LcpProblem c = test::random_contact(20, 60, true, rng, 0.8);
  const solvers::prox::ContinuationOutcome co =
      solvers::prox::continuation_solve(c, Eigen::VectorXd::Zero(c.rows()), continuation_cut_def(), 1e-12, 1);
  EXPECT_EQ(co.solves, 1);
  EXPECT_EQ(co.lambda.size(), c.rows());
}

// Where the parts reach the target the continuation does not run: the same answer, bit for bit.
TEST(ProxNewtonContinuation, DoesNotRunWhereThePartsReachTheTarget) {
  ProxNewtonDef off;
  off.continuation_stages = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 4300);
    const LcpProblem c = test::random_contact(12, 30, true, rng);
    ProxNewtonSolver s;
    const SolveResult r = s.solve(c, {}, test::capped_options());
    ASSERT_EQ(r.status, SolveStatus::Converged) << r.message;
    EXPECT_EQ(s.last_stats().continuation_solves, 0);
    const SolveResult r0 = ProxNewtonSolver(off).solve(c, {}, test::capped_options());
    EXPECT_TRUE(r.lambda == r0.lambda) << "seed " << seed;
  }
}

}  // namespace
}  // namespace dc
