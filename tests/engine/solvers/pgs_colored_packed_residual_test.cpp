// pgs-colored's closing residual on the packed layout (residual/packed_residual.hpp): the natural
// residual of the returned λ as lcp_problem.cpp computes it, to rounding (relative 1e-12), on
// random problems (single contacts, with and without friction) and on a box pyramid (two-point
// manifolds), at ω = 1 and ω ≠ 1, from zero and from non-zero λ⁰; and the same bits from every
// kernel.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "engine/fixed_sweeps.hpp"
#include "lcp/solver_test_problems.hpp"
#include "pgs_colored_kernels.hpp"

namespace dc {
namespace {

/// Every kernel's solve of p from l0 (k sweeps at ω): its residual is the natural residual of its
/// λ to relative 1e-12, and every kernel reports the scalar kernel's bits.
void expect_true_residual(const LcpProblem& p, const Eigen::VectorXd& l0, int k, double omega,
                          const std::string& what) {
  SolverOptions o = test::fixed_sweeps(k);
  o.omega = omega;
  std::vector<double> seen;
  for (PgsColoredDef d : test::pgs_colored_kernel_defs()) {
    d.threads = 1;
    const SolveResult r = make_pgs_colored(d)->solve(p, l0, o);
    ASSERT_TRUE(r.message.empty()) << what << ": " << r.message;  // packed (no "ran pgs")
    const double ref = natural_residual(p, r.lambda);
    ASSERT_TRUE(std::isfinite(ref)) << what;
    EXPECT_LE(std::abs(r.residual - ref), 1e-12 * ref) << what << " kernel " << to_string(d.kernel) << ": "
                                                       << r.residual << " vs " << ref;
    seen.push_back(r.residual);
  }
  for (const double r : seen) EXPECT_EQ(0, std::memcmp(&r, seen.data(), sizeof r)) << what << ": " << r;
}

TEST(PgsColoredPackedResidual, RandomProblemsMatchTheNaturalResidual) {
  for (bool friction : {false, true}) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      test::TestRng rng(seed);
      const LcpProblem p = test::random_contact(60, 90, friction, rng, 0.5, 3);
      Eigen::VectorXd warm(p.rows());
      for (int i = 0; i < p.rows(); ++i) warm[i] = p.normal_row[static_cast<size_t>(i)] < 0 ? rng.uniform(0.0, 1.0) : 0.0;
      for (const double omega : {1.0, 1.3})
        for (const int k : {0, 1, 6, 40}) {
          const std::string what = "friction " + std::to_string(friction) + " seed " + std::to_string(seed) +
                                   " omega " + std::to_string(omega) + " sweeps " + std::to_string(k);
          expect_true_residual(p, Eigen::VectorXd(), k, omega, what);
          expect_true_residual(p, warm, k, omega, what + " warm");
        }
    }
  }
}

TEST(PgsColoredPackedResidual, BoxPyramidMatchesTheNaturalResidual) {
  const LcpProblem p = test::pyramid_problem(6, 20);
  const SolveResult warm = make_solver("pgs")->solve(p, Eigen::VectorXd(), test::fixed_sweeps(30));
  for (const double omega : {1.0, 1.3})
    for (const int k : {0, 2, 6, 60}) {
      const std::string what = "omega " + std::to_string(omega) + " sweeps " + std::to_string(k);
      expect_true_residual(p, Eigen::VectorXd(), k, omega, what);
      expect_true_residual(p, warm.lambda, k, omega, what + " warm");
    }
}

}  // namespace
}  // namespace dc
