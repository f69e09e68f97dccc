// pgs-colored's over-relaxation (SolverOptions::omega, relax/over_relaxation.hpp): at ω ≠ 1 the
// kernels and thread counts stay bit-identical (single contacts and two-point manifolds), the
// iterates differ from ω = 1 (the option acts), the fixed point is "pgs"'s, and ω outside (0, 2)
// is refused as "psor" refuses it.
#include <gtest/gtest.h>

#include <string>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "lcp/solver_test_problems.hpp"
#include "pgs_colored_kernels.hpp"

namespace dc {
namespace {

SolverOptions relaxed(int sweeps, double omega, double tol = 0.0) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = tol;
  o.omega = omega;
  return o;
}

/// Every kernel this CPU runs and 2 threads against the default solver, at `k` sweeps and ω.
void expect_paths_bit_equal(const LcpProblem& p, const Eigen::VectorXd& l0, int k, double omega) {
  PgsColoredDef threaded;
  threaded.threads = 2;
  threaded.min_batches_per_thread = 0;
  const SolveResult s = make_pgs_colored()->solve(p, l0, relaxed(k, omega));
  ASSERT_EQ(s.status, SolveStatus::SweepLimit) << s.message;
  ASSERT_TRUE(s.message.empty()) << s.message;  // the packed sweeps ran, not the pgs fallback
  for (const PgsColoredDef& d : test::pgs_colored_kernel_defs())
    test::expect_bit_equal(s, make_pgs_colored(d)->solve(p, l0, relaxed(k, omega)), to_string(d.kernel));
  test::expect_bit_equal(s, make_pgs_colored(threaded)->solve(p, l0, relaxed(k, omega)), "2 threads");
}

TEST(PgsColoredRelaxation, KernelsAndThreadsAreBitEqualAtOmegaOtherThanOne) {
  for (const bool friction : {false, true}) {
    test::TestRng rng(5);
    const LcpProblem p = test::random_contact(60, 150, friction, rng, 0.5, 4);
    Eigen::VectorXd l0(p.rows());
    for (int i = 0; i < p.rows(); ++i) l0[i] = rng.uniform(-1, 3);
    for (const double omega : {0.7, 1.3})
      for (const int k : {1, 9}) expect_paths_bit_equal(p, l0, k, omega);
  }
  const LcpProblem pyramid = test::pyramid_problem(10, 20);
  for (const int k : {1, 9}) expect_paths_bit_equal(pyramid, Eigen::VectorXd::Zero(pyramid.rows()), k, 1.3);
}

TEST(PgsColoredRelaxation, OmegaChangesTheIteratesButNotTheFixedPoint) {
  for (const bool friction : {false, true}) {
    test::TestRng rng(11);
    // Fewer rows than body dofs: A is non-singular, the solution unique.
    const LcpProblem p = test::random_contact(50, 40, friction, rng, 0.5, 3);
    const SolveResult one = make_pgs_colored()->solve(p, Eigen::VectorXd(), relaxed(3, 1.0));
    const SolveResult over = make_pgs_colored()->solve(p, Eigen::VectorXd(), relaxed(3, 1.3));
    EXPECT_NE(one.lambda, over.lambda) << "friction " << friction;
    const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), relaxed(20000, 1.0, 1e-12));
    for (const double omega : {0.8, 1.3}) {
      const SolveResult c = make_pgs_colored()->solve(p, Eigen::VectorXd(), relaxed(20000, omega, 1e-12));
      ASSERT_EQ(c.status, SolveStatus::Converged) << c.message;
      EXPECT_LE(c.residual, 1e-9);
      EXPECT_LE((a.lambda - c.lambda).cwiseAbs().maxCoeff(), 1e-8 * std::max(1.0, a.lambda.cwiseAbs().maxCoeff()))
          << "friction " << friction << " omega " << omega;
    }
  }
}

TEST(PgsColoredRelaxation, OmegaOutsideZeroTwoIsInvalidInput) {
  test::TestRng rng(3);
  const LcpProblem p = test::random_contact(20, 15, true, rng);
  for (const double omega : {0.0, 2.0, -1.0, 2.5}) {
    const SolveResult r = make_pgs_colored()->solve(p, Eigen::VectorXd(), relaxed(10, omega));
    EXPECT_EQ(r.status, SolveStatus::InvalidInput) << omega;
    EXPECT_NE(r.message.find("omega"), std::string::npos) << r.message;
    EXPECT_TRUE(r.lambda.allFinite());
  }
}

}  // namespace
}  // namespace dc
