#include "solvers/newton_sparse/row_product.hpp"

#include <algorithm>

namespace dc::solvers {

void row_product(const SparseRowMatrix& A, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  const int n = static_cast<int>(A.rows());
  y.resize(n);
  const int* outer = A.outerIndexPtr();
  const int* col = A.innerIndexPtr();
  const double* val = A.valuePtr();
  const double* xs = x.data();
  constexpr int kRows = 4;  // rows whose sums run side by side
  int i = 0;
  for (; i + kRows <= n; i += kRows) {
    int k[kRows], end[kRows];
    double s[kRows];
    for (int r = 0; r < kRows; ++r) {
      k[r] = outer[i + r];
      end[r] = outer[i + r + 1];
      s[r] = 0.0;
    }
    // The entries all four rows have, then each row's rest: per row the order of Eigen's loop.
    int common = end[0] - k[0];
    for (int r = 1; r < kRows; ++r) common = std::min(common, end[r] - k[r]);
    for (int e = 0; e < common; ++e)
      for (int r = 0; r < kRows; ++r) s[r] += val[k[r] + e] * xs[col[k[r] + e]];
    for (int r = 0; r < kRows; ++r) {
      for (int e = k[r] + common; e < end[r]; ++e) s[r] += val[e] * xs[col[e]];
      y[i + r] = s[r];
    }
  }
  for (; i < n; ++i) {
    double s = 0.0;
    for (int e = outer[i]; e < outer[i + 1]; ++e) s += val[e] * xs[col[e]];
    y[i] = s;
  }
}

}  // namespace dc::solvers
