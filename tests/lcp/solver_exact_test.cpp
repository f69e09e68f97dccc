// Exact solvers (lemke, newton) against each other and against the tolerance
// exact_tolerance·max(1,‖b‖∞); iterative solvers converge to their solution; friction.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "dc/lcp/lcp_solver.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

SolveResult run(const std::string& name, const LcpProblem& p, int sweeps = 3000, double tol = 0.0,
                double omega = 1.0) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = tol;
  o.omega = omega;
  return make_solver(name)->solve(p, Eigen::VectorXd(), o);
}

double bound(const LcpProblem& p) {
  double s = 1.0;
  for (int i = 0; i < p.rows(); ++i) s = std::max(s, std::abs(p.b[i]));
  return 1e-9 * s;
}

/// Standard LCP of a contact matrix J M⁻¹ Jᵀ Δt without friction (rank-deficient when
/// there are more contacts than body dofs).
LcpProblem contact_standard(int bodies, int contacts, uint64_t seed) {
  test::TestRng rng(seed);
  const LcpProblem c = test::random_contact(bodies, contacts, false, rng);
  return LcpProblem::standard(Eigen::MatrixXd(c.A), Eigen::VectorXd(c.b));
}

LcpProblem badly_scaled(int n, uint64_t seed) {
  test::TestRng rng(seed);
  const LcpProblem base = test::random_spd(n, rng);
  Eigen::VectorXd d(n);
  for (int i = 0; i < n; ++i) d[i] = std::pow(10.0, -4.0 + 8.0 * i / std::max(1, n - 1));
  const Eigen::MatrixXd A = d.asDiagonal() * Eigen::MatrixXd(base.A) * d.asDiagonal();
  return LcpProblem::standard(A, d.asDiagonal() * base.b);
}

void expect_exact(const std::string& name, const LcpProblem& p, const char* what) {
  const SolveResult r = run(name, p);
  EXPECT_EQ(r.status, SolveStatus::Converged) << name << " on " << what << ": " << r.message;
  EXPECT_LE(r.residual, bound(p)) << name << " on " << what;
  EXPECT_TRUE(r.lambda.allFinite());
}

TEST(SolverExact, MeetTheToleranceOnSpdProblems) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    test::TestRng rng(seed);
    const LcpProblem p = test::random_spd(30, rng);
    expect_exact("lemke", p, "spd");
    expect_exact("newton", p, "spd");
  }
}

TEST(SolverExact, MeetTheToleranceOnSymmetricPsdProblems) {
  test::TestRng rng(21);
  const int n = 25;
  Eigen::MatrixXd B(n, 10);  // rank 10
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 10; ++j) B(i, j) = rng.uniform(-1, 1);
  Eigen::VectorXd q(n);
  for (int i = 0; i < n; ++i) q[i] = rng.uniform(-1, 1);
  // Feasible by construction: q = −B y + s with s ≥ 0 is not needed for PSD LCPs whose
  // q lies in range(B) + cone; take q = B c + |noise| to keep it solvable.
  Eigen::VectorXd cvec(10);
  for (int j = 0; j < 10; ++j) cvec[j] = rng.uniform(-1, 1);
  q = B * cvec + q.cwiseAbs();
  const LcpProblem p = LcpProblem::standard(B * B.transpose(), q);
  expect_exact("lemke", p, "psd");
  expect_exact("newton", p, "psd");
}

TEST(SolverExact, MeetTheToleranceOnRankDeficientContactProblems) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    // 10 bodies = 30 dofs, 60 contacts: A is 60×60 of rank ≤ 30.
    const LcpProblem p = contact_standard(10, 60, seed);
    expect_exact("lemke", p, "contact");
    expect_exact("newton", p, "contact");
  }
}

TEST(SolverExact, MeetTheToleranceOnBadlyScaledProblems) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const LcpProblem p = badly_scaled(20, seed);
    expect_exact("lemke", p, "badly scaled");
    expect_exact("newton", p, "badly scaled");
  }
}

TEST(SolverExact, LemkeAndNewtonAgree) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    test::TestRng rng(seed + 100);
    const LcpProblem p = test::random_spd(40, rng);  // unique solution
    const SolveResult a = run("lemke", p), b = run("newton", p);
    ASSERT_EQ(a.status, SolveStatus::Converged);
    ASSERT_EQ(b.status, SolveStatus::Converged);
    EXPECT_LE((a.lambda - b.lambda).cwiseAbs().maxCoeff(), 1e-7);
  }
  for (uint64_t seed = 1; seed <= 3; ++seed) {  // rank-deficient: λ not unique, w = Aλ + b is
    const LcpProblem p = contact_standard(10, 60, seed);
    const SolveResult a = run("lemke", p), b = run("newton", p);
    EXPECT_LE((lcp_velocity(p, a.lambda) - lcp_velocity(p, b.lambda)).cwiseAbs().maxCoeff(), 1e-6);
  }
}

TEST(SolverExact, IterativeSolversConvergeToTheExactSolution) {
  struct Case {
    const char* name;
    double omega;
  };
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 200);
    const LcpProblem spd = test::random_spd(20, rng);
    // contact-like with fewer contacts than dofs: A positive definite, unique solution
    test::TestRng rng2(seed + 300);
    const LcpProblem contact = test::random_contact(30, 25, false, rng2);
    for (const LcpProblem* p : std::vector<const LcpProblem*>{&spd, &contact}) {
      const SolveResult exact = run("lemke", *p);
      ASSERT_EQ(exact.status, SolveStatus::Converged) << exact.message;
      for (const Case c : {Case{"pgs", 1.0}, Case{"pgs-assembled", 1.0}, Case{"psor", 1.3},
                           Case{"psor", 0.8}, Case{"jacobi", 0.2}}) {
        const SolveResult r = run(c.name, *p, 200000, 1e-11, c.omega);
        EXPECT_EQ(r.status, SolveStatus::Converged) << c.name << " omega " << c.omega << ": " << r.message;
        EXPECT_LE((r.lambda - exact.lambda).cwiseAbs().maxCoeff(), 1e-6) << c.name << " omega " << c.omega;
      }
    }
  }
}

TEST(SolverExact, FrictionSolutionRespectsTheCone) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed + 400);
    const LcpProblem p = test::random_contact(30, 50, true, rng);
    const SolveResult r = run("newton", p);
    ASSERT_EQ(r.status, SolveStatus::Converged) << r.message;
    EXPECT_LE(r.residual, bound(p));
    for (int i = 0; i < p.rows(); ++i) {
      if (p.is_friction_row(i)) {
        const double ln = r.lambda[p.normal_row[static_cast<size_t>(i)]];
        EXPECT_LE(std::abs(r.lambda[i]), p.mu[i] * ln + 1e-9 * std::max(1.0, ln)) << "row " << i;
      } else {
        EXPECT_GE(r.lambda[i], 0.0);
      }
    }
    // PGS reaches the same contact velocities (λ need not be unique, w is for these sizes).
    const SolveResult g = run("pgs", p, 200000, 1e-12);
    EXPECT_EQ(g.status, SolveStatus::Converged) << g.message;
    EXPECT_LT(g.residual, 1e-6);
  }
}

TEST(SolverExact, NewtonSolvesBenchSizedFrictionProblems) {
  // The copy oracle's workload: 100 bodies, ~200 contacts with friction (400 rows). Its speed
  // belongs in the bench (no wall-time assertions in tests); here: it converges.
  test::TestRng rng(500);
  const LcpProblem p = test::random_contact(100, 200, true, rng);
  const SolveResult r = run("newton", p);
  EXPECT_EQ(r.status, SolveStatus::Converged) << r.message;
  EXPECT_LE(r.residual, bound(p));
}

}  // namespace
}  // namespace dc
