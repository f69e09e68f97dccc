#include "world/impulse_parts.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "world/step_parts.hpp"

namespace dc {
namespace {

/// Rows [r0, r1) of Jᵀλ added into out[c0, c1) (entries of other columns skipped). The rows are
/// sorted by body a; the other body's dofs are anywhere unless the bodies follow space, so the
/// last column of the row kAhead rows on is fetched early (a hint).
void add_rows(const SparseRowMatrix& J, const double* lambda, int r0, int r1, int c0, int c1, double* out) {
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  const double* const value = J.valuePtr();
  constexpr int kAhead = 8;
  const bool all = c0 == 0 && c1 == J.cols();
  for (int r = r0; r < r1; ++r) {
    if (r + kAhead < r1 && outer[r + kAhead + 1] > outer[r + kAhead])
      __builtin_prefetch(out + inner[outer[r + kAhead + 1] - 1], 1);
    const double l = lambda[r];
    for (int k = outer[r]; k < outer[r + 1]; ++k) {
      const int c = inner[k];
      if (all || (c >= c0 && c < c1)) out[c] += value[k] * l;
    }
  }
}

}  // namespace

void contact_impulse(const SparseRowMatrix& J, const Eigen::VectorXd& lambda, double dt, Eigen::VectorXd& impulse,
                     int threads, const std::function<void(int, int)>& bodies_done) {
  const int rows = static_cast<int>(J.rows()), cols = static_cast<int>(J.cols());
  const int bodies = (cols + 2) / 3;
  if (!J.isCompressed()) {
    impulse = J.transpose() * lambda * dt;
    bodies_done(0, bodies);
    return;
  }
  const int parts = parts_for(threads, rows, 4, 2048);
  if (parts <= 1) {
    impulse.setZero(cols);
    add_rows(J, lambda.data(), 0, rows, 0, cols, impulse.data());
    impulse *= dt;
    bodies_done(0, bodies);
    return;
  }
  impulse.resize(cols);
  // Block t: bodies [bodies·t/parts, bodies·(t+1)/parts), whole bodies' columns. A row acts on
  // the blocks of its first and its last column (its entries belong to at most two bodies).
  auto block_col = [&](int t) { return std::min(cols, 3 * static_cast<int>(static_cast<long>(bodies) * t / parts)); };
  auto block_of = [&](int col) {
    int t = static_cast<int>(static_cast<long>(col / 3) * parts / std::max(1, bodies));
    while (t + 1 < parts && block_col(t + 1) <= col) ++t;
    while (t > 0 && block_col(t) > col) --t;
    return t;
  };
  // bounds[q·2·parts + t] (lowest) and [… + parts + t] (highest): rows of range q acting on block t.
  std::vector<int> bounds(static_cast<size_t>(2 * parts * parts));
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  run_parts(threads, parts, [&](int q) {
    int* lo = bounds.data() + 2 * parts * q;
    int* hi = lo + parts;
    std::fill(lo, lo + parts, std::numeric_limits<int>::max());
    std::fill(hi, hi + parts, -1);
    const int r1 = static_cast<int>(part_begin(rows, parts, q + 1));
    for (int r = static_cast<int>(part_begin(rows, parts, q)); r < r1; ++r) {
      if (outer[r] == outer[r + 1]) continue;
      for (const int t : {block_of(inner[outer[r]]), block_of(inner[outer[r + 1] - 1])}) {
        lo[t] = std::min(lo[t], r);
        hi[t] = std::max(hi[t], r);
      }
    }
  });
  run_parts(threads, parts, [&](int t) {
    int first = std::numeric_limits<int>::max(), last = -1;
    for (int q = 0; q < parts; ++q) {
      first = std::min(first, bounds[static_cast<size_t>(2 * parts * q + t)]);
      last = std::max(last, bounds[static_cast<size_t>(2 * parts * q + parts + t)]);
    }
    const int c0 = block_col(t), c1 = block_col(t + 1);
    double* out = impulse.data();
    std::fill(out + c0, out + c1, 0.0);
    if (first <= last) add_rows(J, lambda.data(), first, last + 1, c0, c1, out);
    for (int c = c0; c < c1; ++c) out[c] *= dt;
    bodies_done(static_cast<int>(static_cast<long>(bodies) * t / parts), static_cast<int>(static_cast<long>(bodies) * (t + 1) / parts));
  });
}

}  // namespace dc
