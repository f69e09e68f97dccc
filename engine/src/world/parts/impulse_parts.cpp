#include "world/parts/impulse_parts.hpp"

namespace dc {
namespace {

/// True when rows r and r + 1 hold the same columns, strictly ascending (a contact's normal
/// and tangent rows as the assembly writes them).
bool same_columns(const int* outer, const int* inner, int r) {
  const int b = outer[r], e = outer[r + 1];
  if (outer[r + 2] - e != e - b) return false;
  bool same = true;
  for (int k = b; k < e; ++k) same &= inner[k] == inner[k - b + e] && (k + 1 == e || inner[k] < inner[k + 1]);
  return same;
}

/// Rows [0, rows) of Jᵀλ added into out. The rows are sorted by body a; the other body's dofs
/// are anywhere unless the bodies follow space, so the last column of the row kAhead rows on is
/// fetched early (a hint). Two rows with the same columns (a contact's normal and tangent rows)
/// are added column by column: each dof still receives its terms in row order (row r's, then
/// row r + 1's, no other row's between), so every sum is the row-by-row sum, bit for bit.
void add_rows(const SparseRowMatrix& J, const double* lambda, int rows, double* out) {
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  const double* const value = J.valuePtr();
  constexpr int kAhead = 8;
  const auto prefetch = [&](int r) {
    if (r + kAhead < rows && outer[r + kAhead + 1] > outer[r + kAhead])
      __builtin_prefetch(out + inner[outer[r + kAhead + 1] - 1], 1);
  };
  for (int r = 0; r < rows;) {
    prefetch(r);
    const int b = outer[r], e = outer[r + 1];
    if (r + 1 < rows && same_columns(outer, inner, r)) {
      prefetch(r + 1);
      const double l0 = lambda[r], l1 = lambda[r + 1];
      for (int k = b; k < e; ++k) {
        double& o = out[inner[k]];
        o += value[k] * l0;
        o += value[k - b + e] * l1;
      }
      r += 2;
    } else {
      const double l = lambda[r];
      for (int k = b; k < e; ++k) out[inner[k]] += value[k] * l;
      r += 1;
    }
  }
}

}  // namespace

void contact_impulse(const SparseRowMatrix& J, const Eigen::Ref<const Eigen::VectorXd>& lambda, double dt, Eigen::VectorXd& impulse,
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
