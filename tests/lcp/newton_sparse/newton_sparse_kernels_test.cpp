// newton-sparse's GMRES kernels: the interleaved row product (row_product.hpp) and the factor's
// solve with kept CHOLMOD workspace (sparse_factor.hpp) give the bits of Eigen's product and of
// Eigen's CHOLMOD solve, so every newton-sparse and prox-newton result stays what it was.
#include <gtest/gtest.h>

#include <Eigen/CholmodSupport>
#include <cstring>
#include <vector>

#include "lcp/solver_test_problems.hpp"
#include "solvers/newton_sparse/row_product.hpp"
#include "solvers/newton_sparse/sparse_factor.hpp"

namespace dc {
namespace {

bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

/// n × n, row i with a length from 0 to 2·mean (rows of unequal length side by side, empty rows,
/// a count of rows not a multiple of four), values of mixed sign and magnitude.
SparseRowMatrix ragged(int n, int mean, test::TestRng& rng) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    const int len = static_cast<int>(rng.uniform(0, 2.0 * mean + 1));
    for (int k = 0; k < len; ++k)
      t.emplace_back(i, static_cast<int>(rng.uniform(0, n - 1e-9)), rng.uniform(-1, 1) * std::pow(10.0, rng.uniform(-6, 6)));
  }
  SparseRowMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

TEST(NewtonSparseKernels, RowProductIsBitEqualToEigensProduct) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 3100);
    const int n = 37 + static_cast<int>(seed) * 29;  // 66 … 211: every remainder modulo 4
    const SparseRowMatrix A = ragged(n, 13, rng);
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x[i] = rng.uniform(-1, 1) * std::pow(10.0, rng.uniform(-6, 6));
    Eigen::VectorXd eigen(n), ours;
    eigen.noalias() = A * x;
    solvers::row_product(A, x, ours);
    EXPECT_TRUE(same_bits(eigen, ours)) << "seed " << seed << ": max difference " << (eigen - ours).cwiseAbs().maxCoeff();
  }
}

// A symmetric positive definite contact matrix (test::random_contact's A = J M⁻¹ Jᵀ) and a mask
// with a few clamped rows: FreeBlockFactor's solve is Eigen's CHOLMOD solve of the same P, bit
// for bit, on every call (the kept workspace holds no state between calls), and again after a
// bind() to a problem of another size (CHOLMOD reallocates the workspace).
TEST(NewtonSparseKernels, FactorSolveWithKeptWorkspaceIsBitEqualToEigensCholmod) {
  solvers::FreeBlockFactor factor(true, true);
  for (int size : {40, 25, 40}) {
    test::TestRng rng(static_cast<uint64_t>(size) + 3200);
    LcpProblem p = test::random_contact(size, size + 10, true, rng, 0.3);
    p.A.makeCompressed();
    const int n = p.rows();
    std::vector<char> free(static_cast<size_t>(n), 1);
    for (int i = 0; i < n; i += 7) free[static_cast<size_t>(i)] = 0;
    const double rho = 1e-3 * p.A.diagonal().maxCoeff();
    // P by hand: A_FF + ρI on the free rows, the identity on the clamped ones (lower triangle),
    // stored on A's pattern whatever the mask (zeros kept: the ordering follows the pattern).
    using ColMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i) {
      if (!free[static_cast<size_t>(i)]) t.emplace_back(i, i, 1.0);
      else t.emplace_back(i, i, rho);
      for (SparseRowMatrix::InnerIterator e(p.A, i); e; ++e)
        if (e.col() >= i)  // from A's upper triangle, as the factor takes it (A symmetric up to rounding)
          t.emplace_back(static_cast<int>(e.col()), i,
                         free[static_cast<size_t>(i)] && free[static_cast<size_t>(e.col())] ? e.value() : 0.0);
    }
    ColMatrix P(n, n);
    P.setFromTriplets(t.begin(), t.end());
    Eigen::CholmodDecomposition<ColMatrix, Eigen::Lower> reference;
    reference.setMode(Eigen::CholmodLDLt);
    reference.compute(P);
    ASSERT_EQ(reference.info(), Eigen::Success);
    factor.bind(p.A, true);
    NewtonSparseStats st;
    ASSERT_TRUE(factor.factorize(free, rho, st));
    for (int k = 0; k < 3; ++k) {
      Eigen::VectorXd r(n), x;
      for (int i = 0; i < n; ++i) r[i] = rng.uniform(-1, 1);
      factor.solve(r, x);
      const Eigen::VectorXd expected = reference.solve(r);
      EXPECT_TRUE(same_bits(expected, x)) << "size " << size << ", solve " << k;
    }
  }
}

}  // namespace
}  // namespace dc
