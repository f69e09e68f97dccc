#include "world/parts/impulse_parts.hpp"

namespace dc {
namespace {

/// Whether two rows of n entries have the same columns, in strictly ascending order (so that a
/// dof appears once in each).
[[gnu::always_inline]] inline bool same_columns(const int* a, const int* b, int n) {
  bool same = a[0] == b[0];
  for (int i = 1; i < n; ++i) same &= (a[i] == b[i]) & (a[i - 1] < a[i]);
  return same;
}

/// Rows [0, rows) of Jᵀλ added into out. The rows are sorted by body a; the other body's dofs
/// are anywhere unless the bodies follow space, so the last column of the row kAhead rows on is
/// fetched early (a hint). Two consecutive rows over the same columns (a contact's normal and
/// tangent rows) are added in one visit of each dof: out_d + v_r λ_r, then + v_{r+1} λ_{r+1},
/// the sums of the row-by-row order.
void add_rows(const SparseRowMatrix& J, const double* lambda, int rows, double* out) {
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  const double* const value = J.valuePtr();
  constexpr int kAhead = 8;
  for (int r = 0; r < rows;) {
    if (r + kAhead < rows && outer[r + kAhead + 1] > outer[r + kAhead])
      __builtin_prefetch(out + inner[outer[r + kAhead + 1] - 1], 1);
    const int k0 = outer[r], k1 = outer[r + 1];
    const double l = lambda[r];
    if (r + 1 < rows && k1 > k0 && outer[r + 2] - k1 == k1 - k0 && same_columns(inner + k0, inner + k1, k1 - k0)) {
      const double l1 = lambda[r + 1];
      for (int k = k0; k < k1; ++k) {
        double& o = out[inner[k]];
        o = (o + value[k] * l) + value[k + (k1 - k0)] * l1;
      }
      r += 2;
      continue;
    }
    for (int k = k0; k < k1; ++k) out[inner[k]] += value[k] * l;
    ++r;
  }
}

}  // namespace

void contact_impulse(const SparseRowMatrix& J, const Eigen::VectorXd& lambda, double dt, Eigen::VectorXd& impulse,
                     ColumnsDone done) {
  const int cols = static_cast<int>(J.cols());
  if (!J.isCompressed()) {
    impulse = J.transpose() * lambda * dt;
  } else {
    impulse.setZero(cols);
    add_rows(J, lambda.data(), static_cast<int>(J.rows()), impulse.data());
    impulse *= dt;
  }
  done(0, cols);
}

}  // namespace dc
