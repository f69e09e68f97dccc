// pgs-colored's symmetric sweeps (SolverOptions::symmetric): every kernel and a forced thread
// count give the same bits; the first sweep is the forward sweep, the second differs (it runs
// the colours backwards); the fixed point is "pgs"'s.
#include <gtest/gtest.h>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "lcp/solver_test_problems.hpp"
#include "pgs_colored_kernels.hpp"

namespace dc {
namespace {

SolverOptions symmetric(int sweeps, bool on, double tol = 0.0) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = tol;
  o.symmetric = on;
  return o;
}

TEST(PgsColoredSymmetric, KernelsAndThreadsAreBitEqual) {
  const LcpProblem p = test::pyramid_problem(10, 20);
  const Eigen::VectorXd l0 = Eigen::VectorXd::Zero(p.rows());
  PgsColoredDef threaded;
  threaded.threads = 2;
  threaded.min_batches_per_thread = 0;
  for (const int k : {2, 9}) {
    const SolveResult s = make_pgs_colored()->solve(p, l0, symmetric(k, true));
    ASSERT_TRUE(s.message.empty()) << s.message;  // the packed sweeps ran, not the pgs fallback
    for (const PgsColoredDef& d : test::pgs_colored_kernel_defs())
      test::expect_bit_equal(s, make_pgs_colored(d)->solve(p, l0, symmetric(k, true)), to_string(d.kernel));
    test::expect_bit_equal(s, make_pgs_colored(threaded)->solve(p, l0, symmetric(k, true)), "2 threads");
  }
}

TEST(PgsColoredSymmetric, SecondSweepRunsBackwards) {
  const LcpProblem p = test::pyramid_problem(10, 20);
  const Eigen::VectorXd l0 = Eigen::VectorXd::Zero(p.rows());
  test::expect_bit_equal(make_pgs_colored()->solve(p, l0, symmetric(1, false)),
                         make_pgs_colored()->solve(p, l0, symmetric(1, true)), "sweep 1");
  EXPECT_NE(make_pgs_colored()->solve(p, l0, symmetric(2, false)).lambda,
            make_pgs_colored()->solve(p, l0, symmetric(2, true)).lambda);
}

TEST(PgsColoredSymmetric, FixedPointIsPgs) {
  for (const bool friction : {false, true}) {
    test::TestRng rng(11);
    const LcpProblem p = test::random_contact(50, 40, friction, rng, 0.5, 3);  // A non-singular
    const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), symmetric(20000, false, 1e-12));
    const SolveResult c = make_pgs_colored()->solve(p, Eigen::VectorXd(), symmetric(20000, true, 1e-12));
    ASSERT_EQ(c.status, SolveStatus::Converged) << c.message;
    EXPECT_LE((a.lambda - c.lambda).cwiseAbs().maxCoeff(), 1e-8 * std::max(1.0, a.lambda.cwiseAbs().maxCoeff()))
        << "friction " << friction;
  }
}

}  // namespace
}  // namespace dc
