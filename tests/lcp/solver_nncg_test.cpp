// "nncg" (lcp/src/solvers/nncg.cpp): PGS sweeps with nonlinear conjugate-gradient momentum.
// Relationships: the same solution as lemke / pgs where the solution is unique, the first two
// sweeps are pgs's (the momentum starts after the second), fewer sweeps than pgs on a deep
// pile, honest statuses, bit-equal reruns.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dc/lcp/lcp_solver.hpp"
#include "solver_test_problems.hpp"

namespace dc {
namespace {

SolverOptions tolerance_mode(double tol, int cap) {
  SolverOptions o;
  o.max_sweeps = cap;
  o.tolerance = tol;
  o.record_theta = true;
  return o;
}

TEST(SolverNncg, SameSolutionAsLemkeOnStandardProblemsWithAUniqueSolution) {
  test::TestRng rng(31);
  for (int trial = 0; trial < 5; ++trial) {
    // A positive definite A (random SPD; a contact problem with fewer rows than body dofs):
    // exactly one solution.
    for (const LcpProblem& p : {test::random_spd(12, rng), test::random_contact(40, 20, false, rng)}) {
      const SolveResult lemke = make_solver("lemke")->solve(p, {}, SolverOptions{});
      ASSERT_EQ(lemke.status, SolveStatus::Converged) << lemke.message;
      const SolveResult nncg = make_solver("nncg")->solve(p, {}, tolerance_mode(1e-13, 20000));
      ASSERT_EQ(nncg.status, SolveStatus::Converged) << nncg.message;
      EXPECT_LT((nncg.lambda - lemke.lambda).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, lemke.lambda.cwiseAbs().maxCoeff()))
          << "trial " << trial;
      EXPECT_LT(nncg.residual, 1e-9);
    }
  }
}

TEST(SolverNncg, SameSolutionAsPgsWithFriction) {
  test::TestRng rng(32);
  for (int trial = 0; trial < 5; ++trial) {
    // Fewer contacts than bodies: A (normal and tangent rows) is positive definite.
    const LcpProblem p = test::random_contact(40, 15, true, rng);
    const SolveResult pgs = make_solver("pgs")->solve(p, {}, tolerance_mode(1e-13, 50000));
    const SolveResult nncg = make_solver("nncg")->solve(p, {}, tolerance_mode(1e-13, 50000));
    ASSERT_EQ(pgs.status, SolveStatus::Converged) << pgs.message;
    ASSERT_EQ(nncg.status, SolveStatus::Converged) << nncg.message;
    EXPECT_LT((nncg.lambda - pgs.lambda).cwiseAbs().maxCoeff(), 1e-8 * std::max(1.0, pgs.lambda.cwiseAbs().maxCoeff()));
  }
}

TEST(SolverNncg, FirstTwoSweepsArePgsSweeps) {
  // Sweep 1 sets the direction, sweep 2 the first momentum, which moves λ only before sweep 3.
  test::TestRng rng(33);
  const LcpProblem p = test::random_contact(60, 80, true, rng);
  SolverOptions o;
  o.max_sweeps = 2;
  const SolveResult pgs = make_solver("pgs")->solve(p, {}, o);
  const SolveResult nncg = make_solver("nncg")->solve(p, {}, o);
  ASSERT_EQ(nncg.sweeps, 2);
  EXPECT_EQ((nncg.lambda - pgs.lambda).cwiseAbs().maxCoeff(), 0.0);
  o.max_sweeps = 3;
  const SolveResult pgs3 = make_solver("pgs")->solve(p, {}, o);
  const SolveResult nncg3 = make_solver("nncg")->solve(p, {}, o);
  EXPECT_GT((nncg3.lambda - pgs3.lambda).cwiseAbs().maxCoeff(), 0.0) << "no momentum applied before sweep 3";
}

TEST(SolverNncg, FewerSweepsThanPgsOnADeepPile) {
  const LcpProblem p = test::deep_pile(8, 24, 0.5);
  const SolverOptions o = tolerance_mode(1e-4, 30000);  // θ ≤ 1e-4 N, bodies weigh 31 N
  const SolveResult pgs = make_solver("pgs")->solve(p, {}, o);
  const SolveResult nncg = make_solver("nncg")->solve(p, {}, o);
  ASSERT_TRUE(stopped_at_tolerance(nncg.status)) << to_string(nncg.status) << ": " << nncg.message;
  RecordProperty("pgs_sweeps", pgs.sweeps);
  RecordProperty("nncg_sweeps", nncg.sweeps);
  EXPECT_LT(2 * nncg.sweeps, pgs.sweeps) << "pgs " << pgs.sweeps << " (" << to_string(pgs.status) << "), nncg "
                                         << nncg.sweeps;
  EXPECT_LT(nncg.residual, 1e-2);
  // Both are at the same solution of this LCP up to their stopping accuracy.
  EXPECT_LT((nncg.lambda - pgs.lambda).cwiseAbs().maxCoeff(), 1.0);
}

TEST(SolverNncg, ReturnedIteratesAreFeasible) {
  // The momentum is applied before a sweep, so every returned λ is a sweep's projection:
  // λ_n ≥ 0 and |λ_t| ≤ μ λ_n (up to round-off of the clamp) at every checkpoint.
  const LcpProblem p = test::deep_pile(5, 10, 0.3);
  SolverOptions o;
  o.max_sweeps = 200;
  o.checkpoints = {1, 2, 3, 5, 10, 20, 50, 100, 200};
  int seen = 0;
  o.on_checkpoint = [&](int, const Eigen::VectorXd& lam) {
    ++seen;
    for (const ContactConstraint& k : p.constraints) {
      EXPECT_GE(lam[k.normal_row], 0.0);
      EXPECT_LE(std::abs(lam[k.tangent_row]), 0.3 * lam[k.normal_row] + 1e-12);
    }
  };
  make_solver("nncg")->solve(p, {}, o);
  EXPECT_EQ(seen, 9);
}

TEST(SolverNncg, NanGuessIsRefusedWithoutNan) {
  test::TestRng rng(34);
  const LcpProblem p = test::random_contact(20, 30, true, rng);
  Eigen::VectorXd guess = Eigen::VectorXd::Zero(p.rows());
  guess[3] = std::nan("");
  const SolveResult r = make_solver("nncg")->solve(p, guess, tolerance_mode(1e-6, 100));
  EXPECT_EQ(r.status, SolveStatus::InvalidInput);
  EXPECT_TRUE(r.lambda.allFinite());
  EXPECT_EQ(r.lambda.size(), p.rows());
}

TEST(SolverNncg, ReportsSweepLimitWhenTheToleranceIsNotMet) {
  const LcpProblem p = test::deep_pile(6, 16, 0.5);
  const SolveResult r = make_solver("nncg")->solve(p, {}, tolerance_mode(1e-12, 5));
  EXPECT_EQ(r.status, SolveStatus::SweepLimit);
  EXPECT_EQ(r.sweeps, 5);
  EXPECT_TRUE(r.lambda.allFinite());
}

TEST(SolverNncg, RerunsAreBitEqual) {
  test::TestRng rng(35);
  const LcpProblem p = test::random_contact(50, 90, true, rng);
  Eigen::VectorXd guess = Eigen::VectorXd::Constant(p.rows(), 0.1);
  const SolveResult a = make_solver("nncg")->solve(p, guess, tolerance_mode(1e-10, 3000));
  const SolveResult b = make_solver("nncg")->solve(p, guess, tolerance_mode(1e-10, 3000));
  EXPECT_EQ(a.sweeps, b.sweeps);
  EXPECT_EQ(a.theta, b.theta);
  EXPECT_EQ((a.lambda - b.lambda).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SolverNncg, WithoutJacobianRunsTheAssembledFormToTheSameSolution) {
  test::TestRng rng(36);
  const LcpProblem p = test::random_contact(40, 20, true, rng);
  const SolveResult mf = make_solver("nncg")->solve(p, {}, tolerance_mode(1e-12, 20000));
  const SolveResult as = make_solver("nncg")->solve(test::without_jacobian(p), {}, tolerance_mode(1e-12, 20000));
  ASSERT_EQ(mf.status, SolveStatus::Converged) << mf.message;
  ASSERT_EQ(as.status, SolveStatus::Converged) << as.message;
  EXPECT_NE(as.message.find("assembled"), std::string::npos);
  EXPECT_LT((mf.lambda - as.lambda).cwiseAbs().maxCoeff(), 1e-8 * std::max(1.0, mf.lambda.cwiseAbs().maxCoeff()));
}

}  // namespace
}  // namespace dc

namespace dc {
namespace {

/// A = B Bᵀ with B of rank < n (symmetric PSD, singular): where a momentum move can cancel
/// a sweep's change away from a solution.
LcpProblem psd_singular_problem(test::TestRng& rng) {
  const int n = 2 + rng.below(5);
  Eigen::MatrixXd B(n, 1 + rng.below(n - 1));
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = rng.uniform(-1, 1);
  const Eigen::MatrixXd A = B * B.transpose();
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = rng.uniform(-1, 1);
  return LcpProblem::standard(0.5 * (A + A.transpose()), b);
}

/// How far (in units of tol) a pgs sweep may still move λ where nncg stopped on θ ≤ tol.
constexpr double kThetaStopFactor = 10.0;

// θ is what it is for pgs, the change of a sweep: when nncg stops on θ ≤ tol, a pgs sweep
// from the λ it returns moves λ by at most a modest multiple of tol. Counting the momentum
// move in θ (λ_k − λ_{k−1}) let a move that cancelled the sweep's change stop nncg at points
// a pgs sweep moves by orders of magnitude more.
TEST(SolverNncg, ThetaIsTheSweepsOwnChange) {
  test::TestRng rng(2024);
  constexpr double kTol = 1e-8;
  int stops = 0;
  double worst = 0;
  for (int t = 0; t < 1000; ++t) {
    const LcpProblem p = psd_singular_problem(rng);
    const SolveResult r = make_solver("nncg")->solve(p, {}, tolerance_mode(kTol, 5000));
    if (r.status != SolveStatus::ToleranceReached && r.status != SolveStatus::Converged) continue;
    ++stops;
    const SolveResult one = make_solver("pgs-assembled")->solve(p, r.lambda, tolerance_mode(0.0, 1));
    ASSERT_EQ(one.theta.size(), 1u);
    worst = std::max(worst, one.theta[0] / kTol);
  }
  EXPECT_GT(stops, 500);
  EXPECT_LE(worst, kThetaStopFactor) << "a pgs sweep from nncg's stopping point moved λ by " << worst << " × tol";
}

}  // namespace
}  // namespace dc
