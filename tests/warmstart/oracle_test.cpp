// The oracle λ* (solve_oracle) and project_feasible, on small hand-made LCPs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {
namespace {

/// Standard LCP with a random symmetric positive definite A (condition ~ `spread`) and b
/// with mixed signs, so some rows are active and some are not.
LcpProblem random_lcp(int n, double spread, std::uint64_t seed) {
  Rng rng(seed);
  Eigen::MatrixXd M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) M(i, j) = rng.gaussian(1.0);
  Eigen::MatrixXd A = M * M.transpose() + 1e-3 * Eigen::MatrixXd::Identity(n, n);
  // Strong off-diagonal coupling makes PGS slow: A ← A + spread · 1 1ᵀ.
  A += spread * Eigen::MatrixXd::Ones(n, n);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = rng.gaussian(1.0);
  return LcpProblem::standard(A, b);
}

TEST(Oracle, ResidualWithinToleranceFromZeroAndFromAGuess) {
  const LcpProblem p = random_lcp(8, 0.0, 3);
  const OracleSolution s = solve_oracle(p);
  EXPECT_TRUE(s.accurate);
  EXPECT_LE(s.residual, 1e-9 * std::max(1.0, s.lambda.cwiseAbs().maxCoeff()));
  EXPECT_EQ(s.residual, natural_residual(p, s.lambda));
  const Eigen::VectorXd nan_guess = Eigen::VectorXd::Constant(8, std::numeric_limits<double>::quiet_NaN());
  const OracleSolution g = solve_oracle(p, &nan_guess);  // non-finite guess: starts from 0
  EXPECT_TRUE(g.accurate);
  EXPECT_TRUE(g.lambda.allFinite());
}

TEST(Oracle, StageTwoRunsWhenStageOneIsNotAccurate) {
  const LcpProblem p = random_lcp(8, 50.0, 5);
  OracleOptions o;
  o.polish_sweeps = 2;  // far too few for this coupling
  const OracleSolution s = solve_oracle(p, nullptr, o);
  EXPECT_EQ(s.method.rfind(o.iterative + "+" + o.solver, 0), 0u) << s.method;  // stage 2 ran (stage 3 may follow)
  EXPECT_TRUE(s.accurate);
  EXPECT_LE(s.residual, o.tolerance * std::max(1.0, s.lambda.cwiseAbs().maxCoeff()));
  // Stage 1 alone would not have been accurate: the same two sweeps leave a large residual.
  SolverOptions two;
  two.max_sweeps = 2;
  const Eigen::VectorXd pgs2 = make_solver("pgs-assembled")->solve(p, Eigen::VectorXd::Zero(8), two).lambda;
  EXPECT_GT(natural_residual(p, pgs2), 1e3 * s.residual);
}

TEST(Oracle, EveryRouteFindsTheSameUniqueSolution) {
  // SPD A: a unique λ*, so the default route, prox-newton after a newton-sparse stage of one
  // iteration, and no stage 1 at all must agree on it, each within the tolerance.
  const LcpProblem p = random_lcp(8, 50.0, 5);
  OracleOptions defaults, capped, no_stage_one;
  defaults.polish_sweeps = capped.polish_sweeps = 2;  // too few: stage 2 has to run
  capped.solver_iterations = 1;                       // too few: stage 3 has to run
  no_stage_one.iterative = "";
  const OracleSolution a = solve_oracle(p, nullptr, defaults);
  const OracleSolution b = solve_oracle(p, nullptr, capped);
  const OracleSolution c = solve_oracle(p, nullptr, no_stage_one);
  EXPECT_EQ(a.method.rfind("nncg+newton-sparse", 0), 0u) << a.method;
  EXPECT_EQ(b.method, "nncg+newton-sparse+prox-newton");
  EXPECT_EQ(c.method.rfind("guess+", 0), 0u) << c.method;
  for (const OracleSolution* s : {&a, &b, &c}) {
    EXPECT_TRUE(s->accurate) << s->method;
    EXPECT_LE((s->lambda - a.lambda).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, a.lambda.cwiseAbs().maxCoeff()))
        << s->method;
  }
}

TEST(Oracle, EmptyProblem) {
  const OracleSolution s = solve_oracle(LcpProblem::standard(Eigen::MatrixXd(0, 0), Eigen::VectorXd(0)));
  EXPECT_EQ(s.method, "empty");
  EXPECT_TRUE(s.accurate);
  EXPECT_EQ(s.lambda.size(), 0);
}

/// Two contacts of two rows each (normal, tangent) with μ = 0.5, then one fixed-bound row.
LcpProblem friction_problem() {
  LcpProblem p = LcpProblem::standard(Eigen::MatrixXd::Identity(5, 5), Eigen::VectorXd::Zero(5));
  const double inf = std::numeric_limits<double>::infinity();
  for (int t : {1, 3}) {
    p.normal_row[static_cast<size_t>(t)] = t - 1;
    p.mu[t] = 0.5;
    p.lo[t] = -inf;
    p.hi[t] = inf;
  }
  p.lo[4] = -1.0;
  p.hi[4] = 2.0;
  p.validate();
  return p;
}

TEST(ProjectFeasible, ClampsIntoTheFrictionConeAndTheBounds) {
  const LcpProblem p = friction_problem();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd l(5);
  l << 2.0, 3.0, -1.0, 0.7, 5.0;
  project_feasible(p, l);
  EXPECT_EQ(l[0], 2.0);
  EXPECT_EQ(l[1], 1.0);   // |λ_t| ≤ μ λ_n = 1
  EXPECT_EQ(l[2], 0.0);   // λ_n ≥ 0
  EXPECT_EQ(l[3], 0.0);   // … so its friction must vanish
  EXPECT_EQ(l[4], 2.0);   // fixed upper bound
  l << 4.0, -3.0, nan, nan, -7.0;
  project_feasible(p, l);
  EXPECT_EQ(l[1], -2.0);
  EXPECT_EQ(l[2], 0.0);   // NaN → 0
  EXPECT_EQ(l[3], 0.0);
  EXPECT_EQ(l[4], -1.0);
  l << 1.0, 0.25, 1.0, -0.5, 0.0;  // already feasible: unchanged
  const Eigen::VectorXd before = l;
  project_feasible(p, l);
  EXPECT_EQ(l, before);
  l << std::numeric_limits<double>::infinity(), 0.3, 1.0, 0.0, 0.0;
  project_feasible(p, l);
  EXPECT_EQ(l[0], 0.0);  // ±∞ is non-finite too
  EXPECT_EQ(l[1], 0.0);
  Eigen::VectorXd wrong(4);
  EXPECT_THROW(project_feasible(p, wrong), InvalidArgument);
}

}  // namespace
}  // namespace dc
