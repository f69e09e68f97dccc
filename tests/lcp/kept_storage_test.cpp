// KeptVector and KeptSparseRowMatrix (lcp/include/dc/lcp/kept_*.hpp): the storage a World's
// step refills. Resizing within the capacity keeps the block, growing past it at least doubles
// it, and the values read as an Eigen vector's. (That a step then allocates nothing is counted
// by tests/warmstart/settled_step_allocations_test.)
#include <gtest/gtest.h>

#include "dc/lcp/kept_sparse_matrix.hpp"
#include "dc/lcp/kept_vector.hpp"

namespace dc {
namespace {

TEST(KeptVector, ResizeWithinTheCapacityKeepsTheStorage) {
  KeptVector v;
  v.resize(100);
  const double* block = v.data();
  const Eigen::Index held = v.capacity();
  ASSERT_GE(held, 100);
  for (const Eigen::Index n : {40, 99, 7, 100, 0, 63}) {
    v.resize(n);
    EXPECT_EQ(v.size(), n);
    EXPECT_EQ(v.capacity(), held);
    if (n > 0) EXPECT_EQ(v.data(), block);
  }
  v = Eigen::VectorXd::LinSpaced(80, 0.0, 79.0);  // an expression of another size, within it
  EXPECT_EQ(v[79], 79.0);
  v.setZero(90);
  EXPECT_EQ(v.data(), block);
  v.resize(101);  // past it: at least twice as much
  EXPECT_GE(v.capacity(), 2 * held);
}

TEST(KeptVector, ReadsAndAssignsAsAnEigenVector) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(5, 1.0, 5.0);
  KeptVector v = x;
  EXPECT_EQ(v.size(), 5);
  EXPECT_EQ(v.sum(), x.sum());
  EXPECT_EQ(v[3], 4.0);
  v = 2.0 * v;  // aliased, same size
  EXPECT_TRUE((v.array() == 2.0 * x.array()).all());
  v = v.head(3).eval();
  ASSERT_EQ(v.size(), 3);
  EXPECT_EQ(v[2], 6.0);
  v = Eigen::VectorXd::Ones(1000) + v.head(1).replicate(1000, 1);  // grows while reading the old block
  EXPECT_EQ(v[999], 3.0);
  KeptVector w = Eigen::VectorXd::Constant(4, 1.5);
  w = w + w;  // (same size)
  KeptVector copy = w;
  EXPECT_NE(copy.data(), w.data());
  EXPECT_TRUE((copy.array() == 3.0).all());
  const Eigen::Ref<const Eigen::VectorXd> r = copy;  // a view, no copy
  EXPECT_EQ(r.data(), copy.data());
  KeptVector big = Eigen::VectorXd::Zero(50);
  const double* b = big.data();
  big.swap(copy);
  EXPECT_EQ(copy.data(), b);
  EXPECT_EQ(copy.size(), 50);
  EXPECT_EQ(big.size(), 4);
  const Eigen::VectorXd explicit_copy(big);
  EXPECT_TRUE((explicit_copy.array() == 3.0).all());
}

TEST(KeptSparseRowMatrix, ResizeKeepingReusesTheRowIndex) {
  KeptSparseRowMatrix J;
  J.resize_keeping(1000, 30);
  const int* index = J.outerIndexPtr();
  for (const Eigen::Index rows : {10, 999, 500, 1000, 1}) {
    J.resize_keeping(rows, 30);
    EXPECT_EQ(J.rows(), rows);
    EXPECT_EQ(J.cols(), 30);
    EXPECT_EQ(J.nonZeros(), 0);
    EXPECT_EQ(J.outerIndexPtr(), index);
  }
  // Filled as the assembly fills it: one entry per row, then read as a SparseRowMatrix.
  J.resize_keeping(3, 4);
  J.data().resize(3);
  for (int i = 0; i < 3; ++i) {
    J.outerIndexPtr()[i] = i;
    J.data().index(i) = i + 1;
    J.data().value(i) = 2.0 * i;
  }
  J.outerIndexPtr()[3] = 3;
  const SparseRowMatrix& base = J;
  EXPECT_EQ(Eigen::MatrixXd(base)(2, 3), 4.0);
  EXPECT_EQ(Eigen::MatrixXd(base)(0, 1), 0.0);
  J.resize_keeping(5000, 4);  // past the block: a larger one
  EXPECT_EQ(J.rows(), 5000);
  EXPECT_EQ(J.outerIndexPtr()[5000], 0);
}

}  // namespace
}  // namespace dc
