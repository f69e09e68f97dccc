#pragma once
// A row-major sparse matrix whose row index keeps its storage when the row count changes, for
// the Jacobian J a World refills every step: Eigen's SparseMatrix::resize frees and allocates
// its outer index whenever the outer size changes (its entries, CompressedStorage, keep their
// capacity already), so a pile that gains rows every step would allocate it every step.
#include <Eigen/SparseCore>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dc {

using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

/// A SparseRowMatrix (every reader takes it as one, by reference) with one more operation,
/// resize_keeping(): Eigen's resize() that reuses the row index's block while it is large
/// enough, and otherwise allocates max(rows + 1, 2·(rows + 1 of before)) entries. The capacity
/// is asked of the allocator (malloc_usable_size, glibc), never remembered, so any Eigen
/// operation that reallocates the index in between (assignment, resize, swap) cannot leave a
/// stale capacity behind; without glibc the capacity known is the current row count's.
class KeptSparseRowMatrix : public SparseRowMatrix {
 public:
  using SparseRowMatrix::SparseRowMatrix;
  using SparseRowMatrix::operator=;
  KeptSparseRowMatrix() = default;
  KeptSparseRowMatrix(const SparseRowMatrix& other) : SparseRowMatrix(other) {}  // NOLINT(google-explicit-constructor)

  /// rows × cols, no entries (compressed), as SparseMatrix::resize leaves it.
  void resize_keeping(Eigen::Index rows, Eigen::Index cols) {
    if (m_outerIndex == nullptr || m_innerNonZeros != nullptr) {  // first use, or uncompressed: Eigen's
      resize(rows, cols);
      return;
    }
    const std::size_t need = static_cast<std::size_t>(rows + 1) * sizeof(StorageIndex);
    if (index_capacity() < need) {
      const std::size_t bytes = std::max(need, 2 * static_cast<std::size_t>(m_outerSize + 1) * sizeof(StorageIndex));
      auto* index = static_cast<StorageIndex*>(std::malloc(bytes));  // freed by ~SparseMatrix (std::free)
      if (index == nullptr) Eigen::internal::throw_std_bad_alloc();
      std::free(m_outerIndex);
      m_outerIndex = index;
    }
    m_outerSize = rows;
    m_innerSize = cols;
    m_data.clear();
    std::memset(m_outerIndex, 0, need);
  }

 private:
  /// Bytes of the row index's block (where the allocator cannot tell: the current row count's).
  [[nodiscard]] std::size_t index_capacity() const {
#if defined(__GLIBC__)
    return m_outerIndex == nullptr ? 0 : malloc_usable_size(m_outerIndex);
#else
    return static_cast<std::size_t>(m_outerSize + 1) * sizeof(StorageIndex);
#endif
  }
};

}  // namespace dc
