#include "world/parts/impulse_parts.hpp"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "dc/core/block_row_ranges.hpp"
#include "world/parts/step_parts.hpp"

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
                     int threads) {
  const int rows = static_cast<int>(J.rows()), cols = static_cast<int>(J.cols());
  const int bodies = (cols + 2) / 3;
  if (!J.isCompressed()) {
    impulse = J.transpose() * lambda * dt;
    return;
  }
  const int parts = parts_for(threads, rows, 1, 2048);  // blocks: a row range can reach several
  if (parts <= 1) {
    impulse.setZero(cols);
    add_rows(J, lambda.data(), 0, rows, 0, cols, impulse.data());
    impulse *= dt;
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
  // Per range q of rows and block t, the lowest and highest row acting on t, apart for rows of
  // one body (walls: they come first and reach every block) and of two: bounds[(q·parts + t)·4
  // + {0, 1}] and [… + {2, 3}].
  constexpr int kMax = std::numeric_limits<int>::max();
  std::vector<int> bounds(static_cast<size_t>(4 * parts * parts));
  const int* const outer = J.outerIndexPtr();
  const int* const inner = J.innerIndexPtr();
  run_parts(threads, parts, [&](int q) {
    int* b = bounds.data() + 4 * parts * q;
    for (int t = 0; t < parts; ++t) {
      b[4 * t] = b[4 * t + 2] = kMax;
      b[4 * t + 1] = b[4 * t + 3] = -1;
    }
    const int r1 = static_cast<int>(part_begin(rows, parts, q + 1));
    for (int r = static_cast<int>(part_begin(rows, parts, q)); r < r1; ++r) {
      if (outer[r] == outer[r + 1]) continue;
      const int first = inner[outer[r]], last = inner[outer[r + 1] - 1];
      const int kind = first / 3 == last / 3 ? 0 : 2;
      for (const int t : {block_of(first), block_of(last)}) {
        b[4 * t + kind] = std::min(b[4 * t + kind], r);
        b[4 * t + kind + 1] = std::max(b[4 * t + kind + 1], r);
      }
    }
  });
  run_parts(threads, parts, [&](int t) {
    const BlockRowRanges r = block_row_ranges(bounds.data(), parts, t);
    const int c0 = block_col(t), c1 = block_col(t + 1);
    double* out = impulse.data();
    std::fill(out + c0, out + c1, 0.0);
    if (r.lo1 <= r.hi1) add_rows(J, lambda.data(), r.lo1, r.hi1 + 1, c0, c1, out);
    if (r.lo2 <= r.hi2) add_rows(J, lambda.data(), r.lo2, r.hi2 + 1, c0, c1, out);
    for (int c = c0; c < c1; ++c) out[c] *= dt;
  });
}

}  // namespace dc
