// Edge cases (docs/robustness.md, docs/lcp.md): every solver returns a status that says what happened,
// never hangs and never returns NaN.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

SolveResult run(const std::string& name, const LcpProblem& p, int sweeps = 500) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = 1e-10;
  o.omega = name == "jacobi" ? 0.5 : 1.0;
  return make_solver(name)->solve(p, Eigen::VectorXd(), o);
}

LcpProblem dense(std::initializer_list<std::initializer_list<double>> rows, std::initializer_list<double> q) {
  const int n = static_cast<int>(q.size());
  Eigen::MatrixXd A(n, n);
  int i = 0;
  for (const auto& r : rows) {
    int j = 0;
    for (double v : r) A(i, j++) = v;
    ++i;
  }
  return LcpProblem::standard(A, Eigen::Map<const Eigen::VectorXd>(q.begin(), n));
}

void expect_sane(const SolveResult& r, int n, const std::string& what) {
  EXPECT_EQ(r.lambda.size(), n) << what;
  EXPECT_TRUE(r.lambda.allFinite()) << what;
  EXPECT_FALSE(std::isnan(r.residual)) << what;
}

TEST(SolverEdge, UnknownNameListsTheValidOnes) {
  try {
    (void)make_solver("gauss");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("pgs-assembled"), std::string::npos);
  }
  for (const auto& name : solver_names()) EXPECT_EQ(make_solver(name)->name(), name);
}

TEST(SolverEdge, StatusNames) {
  EXPECT_STREQ(to_string(SolveStatus::Converged), "converged");
  EXPECT_STREQ(to_string(SolveStatus::Infeasible), "infeasible");
}

TEST(SolverEdge, InvalidProblemsAndGuessesAreInvalidInput) {
  LcpProblem p = dense({{2, 0}, {0, 2}}, {-1, -1});
  p.b[1] = NAN;
  for (const auto& name : solver_names()) {
    const SolveResult r = run(name, p);
    EXPECT_EQ(r.status, SolveStatus::InvalidInput) << name;
    EXPECT_FALSE(r.message.empty());
    EXPECT_TRUE(r.lambda.allFinite());
  }
  const LcpProblem ok = dense({{2, 0}, {0, 2}}, {-1, -1});
  SolverOptions o;
  for (const auto& name : solver_names()) {
    EXPECT_EQ(make_solver(name)->solve(ok, Eigen::VectorXd::Zero(3), o).status, SolveStatus::InvalidInput) << name;
    EXPECT_EQ(make_solver(name)->solve(ok, Eigen::Vector2d(NAN, 0), o).status, SolveStatus::InvalidInput) << name;
  }
  o.omega = 2.5;
  EXPECT_EQ(make_solver("psor")->solve(ok, Eigen::VectorXd(), o).status, SolveStatus::InvalidInput);
  EXPECT_EQ(make_solver("jacobi")->solve(ok, Eigen::VectorXd(), o).status, SolveStatus::InvalidInput);
}

TEST(SolverEdge, LemkeRejectsFrictionProblems) {
  test::TestRng rng(1);
  const LcpProblem p = test::random_contact(5, 5, true, rng);
  EXPECT_EQ(run("lemke", p).status, SolveStatus::InvalidInput);
}

TEST(SolverEdge, NonNegativeQIsSolvedByZero) {
  const LcpProblem p = dense({{1, 2}, {3, -4}}, {0.5, 0.0});
  const SolveResult r = run("lemke", p);
  EXPECT_EQ(r.status, SolveStatus::Converged);
  EXPECT_EQ(r.sweeps, 0);
  EXPECT_EQ(r.lambda, Eigen::Vector2d::Zero());
  EXPECT_EQ(run("newton", p).status, SolveStatus::Converged);
}

TEST(SolverEdge, OneRow) {
  const LcpProblem p = dense({{4}}, {-2});
  for (const auto& name : solver_names()) {
    const SolveResult r = run(name, p);
    EXPECT_EQ(r.status, SolveStatus::Converged) << name << ": " << r.message;
    EXPECT_NEAR(r.lambda[0], 0.5, 1e-9) << name;
  }
}

TEST(SolverEdge, EmptyProblem) {
  const LcpProblem p = LcpProblem::standard(Eigen::MatrixXd(0, 0), Eigen::VectorXd(0));
  for (const auto& name : solver_names()) {
    const SolveResult r = run(name, p);
    expect_sane(r, 0, name);
    EXPECT_NE(r.status, SolveStatus::Diverged) << name;
  }
}

TEST(SolverEdge, ZeroMatrixWithNegativeQIsInfeasible) {
  const LcpProblem p = dense({{0, 0}, {0, 0}}, {-1, -2});
  for (const auto& name : solver_names()) {
    const SolveResult r = run(name, p);
    expect_sane(r, 2, name);
    EXPECT_NE(r.status, SolveStatus::Converged) << name;
    EXPECT_NE(r.status, SolveStatus::SweepLimit) << name;
  }
  EXPECT_EQ(run("lemke", p).status, SolveStatus::Infeasible);
}

TEST(SolverEdge, ZeroDiagonalAndZeroRows) {
  // Row 1 is all zero with q ≥ 0: λ_1 = 0 is complementary, nothing fails.
  const LcpProblem zero_row = dense({{2, 0, 1}, {0, 0, 0}, {1, 0, 3}}, {-1, 0.5, -1});
  for (const auto& name : solver_names()) {
    const SolveResult r = run(name, zero_row, 5000);
    expect_sane(r, 3, name);
    EXPECT_EQ(r.status, SolveStatus::Converged) << name << ": " << r.message;
    EXPECT_LT(r.residual, 1e-8) << name;
  }
  // Zero diagonal in a coupled row: M = [[0, 1], [1, 2]], q = (1, -1) has the solution
  // z = (0, 0.5) (w_0 = 1.5 ≥ 0); the sweep methods must not divide by 0.
  const LcpProblem zero_diag = dense({{0, 1}, {1, 2}}, {1, -1});
  for (const auto& name : solver_names()) {
    const SolveResult r = run(name, zero_diag, 5000);
    expect_sane(r, 2, name);
    EXPECT_EQ(r.status, SolveStatus::Converged) << name << ": " << r.message;
    EXPECT_NEAR(r.lambda[1], 0.5, 1e-8) << name;
  }
  // Zero diagonal that must be pushed: M = [[0, -1], [1, 2]], q = (-1, 0): for the sweep
  // methods row 0 cannot be solved by a diagonal step; they report Failed, not NaN.
  const LcpProblem stuck = dense({{0, 0}, {0, 1}}, {-1, -1});
  for (const auto& name : {"pgs", "pgs-assembled", "psor", "jacobi"}) {
    const SolveResult r = run(name, stuck, 100);
    expect_sane(r, 2, name);
    EXPECT_EQ(r.status, SolveStatus::Failed) << name << ": " << r.message;
    EXPECT_NE(r.message.find("diagonal"), std::string::npos) << r.message;
  }
}

TEST(SolverEdge, InfeasibleProblemsAreReportedByLemke) {
  // Skew-symmetric (PSD, copositive-plus) with w_0 = −z_1 − 1 < 0 always.
  const LcpProblem skew = dense({{0, -1}, {1, 0}}, {-1, -1});
  // Negative definite with q < 0: w = −z − 1 < 0.
  const LcpProblem negdef = dense({{-1, 0}, {0, -1}}, {-1, -1});
  for (const LcpProblem* p : std::vector<const LcpProblem*>{&skew, &negdef}) {
    EXPECT_EQ(run("lemke", *p).status, SolveStatus::Infeasible);
    for (const auto& name : solver_names()) {
      const SolveResult r = run(name, *p);
      expect_sane(r, 2, name);
      EXPECT_NE(r.status, SolveStatus::Converged) << name;
      EXPECT_FALSE(r.message.empty()) << name;
    }
  }
}

TEST(SolverEdge, ValuesNearOverflow) {
  const LcpProblem big = dense({{1e300, 0}, {0, 1e300}}, {-1e300, -1e299});
  for (const auto& name : solver_names()) {
    const SolveResult r = run(name, big);
    expect_sane(r, 2, name);
    EXPECT_EQ(r.status, SolveStatus::Converged) << name << ": " << r.message;
    EXPECT_NEAR(r.lambda[0], 1.0, 1e-9) << name;
  }
  // Huge off-diagonal coupling: products overflow in the iterations of some methods.
  const LcpProblem wild = dense({{1e-300, 1e300}, {-1e300, 1e-300}}, {-1e300, 1e300});
  for (const auto& name : solver_names()) {
    const SolveResult r = run(name, wild);
    expect_sane(r, 2, name);
  }
}

TEST(SolverEdge, NoSolverHangsOnNonConvergingIterations) {
  // Every solver, on a strongly coupled matrix (projected Jacobi without damping diverges on
  // it) and on an LCP without a solution (w = −λ − 1 ≥ 0 cannot hold for λ ≥ 0): each returns
  // within its sweep limit, with a finite iterate, and claims convergence only when it is true.
  const LcpProblem coupled = dense({{1, 0.9, 0.9}, {0.9, 1, 0.9}, {0.9, 0.9, 1}}, {-1, -1, -1});
  const LcpProblem unsolvable = dense({{1, 0}, {0, -1}}, {-1, -1});
  SolverOptions o;
  o.max_sweeps = 100000;
  o.tolerance = 1e-12;
  for (const std::string& name : solver_names()) {
    for (const LcpProblem* p : {&coupled, &unsolvable}) {
      const std::string what = name + (p == &coupled ? " coupled" : " unsolvable");
      const SolveResult r = make_solver(name)->solve(*p, Eigen::VectorXd(), o);
      if (r.status == SolveStatus::InvalidInput) {
        EXPECT_EQ(p, &unsolvable) << what << ": " << r.message;  // only a negative pivot may be refused
        continue;
      }
      expect_sane(r, p->rows(), what);
      EXPECT_LE(r.sweeps, o.max_sweeps) << what;
      if (r.status == SolveStatus::Converged) {
        EXPECT_LE(natural_residual(*p, r.lambda), 1e-6) << what;
      } else {
        EXPECT_FALSE(r.message.empty()) << what;
      }
      if (p == &unsolvable) {
        EXPECT_NE(r.status, SolveStatus::Converged) << what;
      }
    }
  }
  const SolveResult j = make_solver("jacobi")->solve(coupled, Eigen::VectorXd(), o);
  EXPECT_NE(j.status, SolveStatus::Converged);
}

// The natural map in two norms: 0 together at a solution, ‖r‖∞ ≤ ‖r‖₂ ≤ √n ‖r‖∞ elsewhere,
// and the 2-norm equal to the rows' map computed by hand.
TEST(NaturalResidual, TwoNormAgreesWithTheMaxNormAndTheMapByHand) {
  const LcpProblem p = dense({{2, 1, 0}, {1, 3, 1}, {0, 1, 4}}, {-1, 2, -3});
  const Eigen::VectorXd lambda = Eigen::Vector3d(0.2, 0.7, -0.1);  // infeasible on purpose
  const Eigen::VectorXd w = lcp_velocity(p, lambda);
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double e = lambda[i] - std::max(0.0, lambda[i] - w[i]);  // lo = 0, hi = +∞
    sum += e * e;
  }
  const double inf = natural_residual(p, lambda), two = natural_residual_l2(p, lambda);
  EXPECT_NEAR(two, std::sqrt(sum), 1e-12);
  EXPECT_LE(inf, two + 1e-15);
  EXPECT_LE(two, std::sqrt(3.0) * inf + 1e-15);
  const SolveResult r = run("lemke", p);
  ASSERT_EQ(r.status, SolveStatus::Converged);
  EXPECT_LE(natural_residual_l2(p, r.lambda), 1e-9);
  EXPECT_EQ(natural_residual_l2(p, Eigen::Vector3d(std::nan(""), 0, 0)), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace dc
