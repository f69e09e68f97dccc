#include "world/parts/impulse_parts.hpp"

namespace dc {
namespace {

/// Rows [0, rows) of Jᵀλ added into out. The rows are sorted by body a; the other body's dofs
/// are anywhere unless the bodies follow space, so the last column of the row kAhead rows on is
/// fetched early (a hint).
void add_rows(const SparseRowMatrix& J, const double* lambda, int rows, double* out) {
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  const double* const value = J.valuePtr();
  constexpr int kAhead = 8;
  for (int r = 0; r < rows; ++r) {
    if (r + kAhead < rows && outer[r + kAhead + 1] > outer[r + kAhead])
      __builtin_prefetch(out + inner[outer[r + kAhead + 1] - 1], 1);
    const double l = lambda[r];
    for (int k = outer[r]; k < outer[r + 1]; ++k) out[inner[k]] += value[k] * l;
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
