// White-box tests of the private active-set helpers (warmstart/include/dc/warmstart/active_set_solve.hpp):
// the minimum-norm solve behind copy-active and builtin-active, and the contact modes.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "dc/warmstart/active_set_solve.hpp"

namespace dc {
namespace {

/// An orthogonal matrix from the QR of a seeded random one.
Eigen::MatrixXd random_orthogonal(int n, unsigned seed) {
  std::srand(seed);
  const Eigen::MatrixXd r = Eigen::MatrixXd::Random(n, n);
  return Eigen::HouseholderQR<Eigen::MatrixXd>(r).householderQ() * Eigen::MatrixXd::Identity(n, n);
}

/// Frees NaN-filled blocks of the sizes a decomposition of order n allocates, so that memory
/// it reads without writing is NaN rather than a lucky zero.
void poison_heap(int n) {
  for (int k = 1; k <= 4 * n + 16; ++k) {
    auto block = std::make_unique<double[]>(static_cast<std::size_t>(k));
    for (int i = 0; i < k; ++i) block[static_cast<std::size_t>(i)] = std::numeric_limits<double>::quiet_NaN();
  }
}

TEST(MinNormSolve, MatchesTheTruncatedPseudoInverseWhenAPivotLiesBelowTheThreshold) {
  // M = U diag(1, 0.5, 0.2, 1e-12, 0, 0) Vᵀ: with the threshold 1e-10 the 1e-12 direction is
  // null, so the answer is V diag(1, 2, 5, 0, 0, 0) Uᵀ rhs, the truncated pseudo-inverse.
  // The default threshold (ε · 6) would keep it and answer ~1e12 along it.
  const int n = 6;
  const Eigen::MatrixXd U = random_orthogonal(n, 3), V = random_orthogonal(n, 5);
  Eigen::VectorXd s(n), s_inv(n);
  s << 1, 0.5, 0.2, 1e-12, 0, 0;
  s_inv << 1, 2, 5, 0, 0, 0;
  const Eigen::MatrixXd M = U * s.asDiagonal() * V.transpose();
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  const Eigen::VectorXd expected = V * s_inv.asDiagonal() * U.transpose() * rhs;
  for (int repeat = 0; repeat < 3; ++repeat) {
    poison_heap(n);
    const Eigen::VectorXd y = min_norm_solve(M, rhs, 1e-10);
    ASSERT_TRUE(y.allFinite());
    EXPECT_LT((y - expected).norm(), 1e-8 * expected.norm()) << "repeat " << repeat;
  }
}

TEST(MinNormSolve, SolvesANonSingularSystemExactly) {
  const int n = 5;
  const Eigen::MatrixXd M = random_orthogonal(n, 7) * Eigen::VectorXd::LinSpaced(n, 1.0, 3.0).asDiagonal() *
                            random_orthogonal(n, 9).transpose();
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(n, 0.5, -2.0);
  const Eigen::VectorXd y = min_norm_solve(M, rhs, 1e-10);
  EXPECT_LT((M * y - rhs).norm(), 1e-12);
}

}  // namespace
}  // namespace dc
