#include "solvers/prox_newton/body/normal_matrix.hpp"

#include <algorithm>
#include <cstddef>

namespace dc::solvers::prox {
namespace {

/// One past row r's last stored entry (compressed or not).
int row_end(const SparseRowMatrix& J, int r) {
  return J.isCompressed() ? J.outerIndexPtr()[r + 1] : J.outerIndexPtr()[r] + J.innerNonZeroPtr()[r];
}

}  // namespace

void NormalMatrix::bind(const SparseRowMatrix& J, const SparseRowMatrix& Jt) {
  const int m = static_cast<int>(J.cols());
  const int n = static_cast<int>(J.rows());
  const int* outer = J.outerIndexPtr();
  const int* inner = J.innerIndexPtr();
  pair_start_.assign(static_cast<size_t>(n) + 1, 0);
  for (int r = 0; r < n; ++r) {
    const int nr = row_end(J, r) - outer[r];
    pair_start_[static_cast<size_t>(r) + 1] = pair_start_[static_cast<size_t>(r)] + nr * nr;
  }
  slot_.resize(static_cast<size_t>(pair_start_.back()));
  diag_slot_.resize(static_cast<size_t>(m));
  mark_.assign(static_cast<size_t>(m), -1);
  pos_.resize(static_cast<size_t>(m));
  cols_.clear();
  row_start_.assign(static_cast<size_t>(m) + 1, 0);
  // Row a of H: the diagonal and every column b sharing a row r of J with a (r from Jᵀ's row a),
  // sorted; then the slots of the pairs (a, ·) of each such row r.
  for (int a = 0; a < m; ++a) {
    const auto begin = static_cast<std::ptrdiff_t>(cols_.size());
    mark_[static_cast<size_t>(a)] = a;
    cols_.push_back(a);
    for (SparseRowMatrix::InnerIterator t(Jt, a); t; ++t)
      for (int l = outer[t.index()]; l < row_end(J, static_cast<int>(t.index())); ++l)
        if (mark_[static_cast<size_t>(inner[l])] != a) {
          mark_[static_cast<size_t>(inner[l])] = a;
          cols_.push_back(inner[l]);
        }
    std::sort(cols_.begin() + begin, cols_.end());
    for (auto i = static_cast<size_t>(begin); i < cols_.size(); ++i)
      pos_[static_cast<size_t>(cols_[i])] = static_cast<int>(i);
    diag_slot_[static_cast<size_t>(a)] = pos_[static_cast<size_t>(a)];
    for (SparseRowMatrix::InnerIterator t(Jt, a); t; ++t) {
      const int r = static_cast<int>(t.index()), b0 = outer[r], e = row_end(J, r);
      const int k = static_cast<int>(std::find(inner + b0, inner + e, a) - inner);
      int* slot = slot_.data() + pair_start_[static_cast<size_t>(r)] + (k - b0) * (e - b0);
      for (int l = b0; l < e; ++l) *slot++ = pos_[static_cast<size_t>(inner[l])];
    }
    row_start_[static_cast<size_t>(a) + 1] = static_cast<int>(cols_.size());
  }
  H_.resize(m, m);
  H_.resizeNonZeros(static_cast<Eigen::Index>(cols_.size()));
  std::copy(row_start_.begin(), row_start_.end(), H_.outerIndexPtr());
  std::copy(cols_.begin(), cols_.end(), H_.innerIndexPtr());
  std::fill(H_.valuePtr(), H_.valuePtr() + H_.nonZeros(), 0.0);
}

void NormalMatrix::assemble(const SparseRowMatrix& J, const Eigen::VectorXd& winv, const Eigen::VectorXd& d) {
  const int* outer = J.outerIndexPtr();
  const double* jv = J.valuePtr();
  double* hv = H_.valuePtr();
  std::fill(hv, hv + H_.nonZeros(), 0.0);
  for (int r = 0; r < static_cast<int>(J.rows()); ++r) {
    const double dr = d[r];
    if (dr == 0.0) continue;  // adds ±0 to every entry of the row's pairs: no value changes
    const int* slot = slot_.data() + pair_start_[static_cast<size_t>(r)];
    const int e = row_end(J, r);
    for (int k = outer[r]; k < e; ++k)
      for (int l = outer[r]; l < e; ++l) hv[*slot++] += (dr * jv[l]) * jv[k];  // Eigen's (DJ)_rb · Jᵀ_ar
  }
  for (size_t a = 0; a < diag_slot_.size(); ++a) hv[diag_slot_[a]] += winv[static_cast<Eigen::Index>(a)];
}

}  // namespace dc::solvers::prox
