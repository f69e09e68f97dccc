// The products with J around pgs-colored's sweeps, bit-identical to the serial forms
// (pgs_colored_products.hpp).
#include "solvers/pgs_colored/pgs_colored_products.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "dc/core/block_row_ranges.hpp"
#include "dc/core/work_team.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_residual.hpp"

namespace dc::colored {

namespace {

/// du from jt = Jᵀλ (velocity_change's layout: body k at Δu slot slot[k], or k without `slot`);
/// whether every entry is finite.
bool scale_to_du(const LcpProblem& p, const Eigen::VectorXd& jt, int bodies, double* du, const int* slot = nullptr) {
  // Every entry written once (no zero-fill first): a body's three velocities, 0 for columns past
  // J's and for the padding entry; then the zero body. The finiteness test rides along (no
  // second pass over Δu).
  const int ncols = static_cast<int>(jt.size());
  const double* im = p.inv_mass.data();
  const double* v = jt.data();
  const double dt = p.dt;
  const int whole = std::min(ncols / 3, bodies);
  std::uint64_t bad = 0;
  auto entry = [&](int k) { return du + static_cast<size_t>(kStride) * static_cast<size_t>(slot ? slot[k] : k); };
  for (int k = 0; k < whole; ++k) {
    double* out = entry(k);
    const int c = 3 * k;
    out[0] = im[c] * v[c] * dt;
    out[1] = im[c + 1] * v[c + 1] * dt;
    out[2] = im[c + 2] * v[c + 2] * dt;
    out[3] = 0.0;
    bad |= not_finite_bit(out[0]) | not_finite_bit(out[1]) | not_finite_bit(out[2]);
  }
  for (int k = whole; k < bodies; ++k) {  // a body with fewer than three columns in J
    double* out = entry(k);
    for (int d = 0; d < 3; ++d) {
      const int c = 3 * k + d;
      out[d] = c < ncols ? im[c] * v[c] * dt : 0.0;
      bad |= not_finite_bit(out[d]);
    }
    out[3] = 0.0;
  }
  std::fill(du + static_cast<size_t>(kStride) * bodies, du + static_cast<size_t>(kStride) * (bodies + 1), 0.0);
  return bad == 0;
}

}  // namespace

bool velocity_change(const LcpProblem& p, const Eigen::VectorXd& lambda, int bodies, double* du,
                     Eigen::VectorXd& jt, bool skip_zero) {
  // Jᵀλ into a kept buffer, as Eigen's product sums it: a contiguous scatter is faster than one
  // straight into the strided Δu (c/3 and c%3 per entry).
  jt.setZero(p.J.cols());
  transpose_rows(p, lambda.data(), 0, p.rows(), 0, static_cast<int>(p.J.cols()), jt.data(), skip_zero);
  return scale_to_du(p, jt, bodies, du);
}

bool velocity_change_checked(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, int bodies, double* du,
                             Eigen::VectorXd& jt, bool& j_finite, const int* slot, bool check) {
  jt.setZero(p.J.cols());
  j_finite = transpose_rows_checked(p, lambda.data(), jt.data(), check);
  return scale_to_du(p, jt, bodies, du, slot);
}

namespace {

/// First body of block t of nt over `bodies` bodies (contiguous blocks of near-equal size).
int block_begin(int bodies, int t, int nt) { return static_cast<int>(static_cast<long>(bodies) * t / nt); }

/// The block holding body b; begin[t] = block_begin(bodies, t, nt) for t ≤ nt (a search, not a
/// division: this runs twice per contact).
int block_of(const int* begin, int nt, int b) {
  if (nt <= 8) {
    int t = 0;
    while (t + 1 < nt && begin[t + 1] <= b) ++t;
    return t;
  }
  return static_cast<int>(std::upper_bound(begin + 1, begin + nt, b) - (begin + 1));
}

/// Part tid of nt of scaled_transpose_product's first phase: from the part's share of the
/// contacts, per block t of bodies, the lowest and highest row acting on it, apart for contacts
/// with one body (walls: they come first and reach every block) and with two:
/// bounds[(tid·nt + t)·4 + {0, 1}] and [… + {2, 3}] (bounds holds 4·nt·nt ints, shared).
void transpose_bounds(const LcpProblem& p, int tid, int nt, int* bounds) {
  const int ncols = static_cast<int>(p.J.cols());
  const int bodies = (ncols + 2) / 3;
  const ContactConstraints& cons = p.constraints;
  std::vector<int> begin(static_cast<size_t>(nt) + 1);
  for (int t = 0; t <= nt; ++t) begin[static_cast<size_t>(t)] = block_begin(bodies, t, nt);
  int* b = bounds + 4 * nt * tid;
  for (int t = 0; t < nt; ++t) {
    b[4 * t] = b[4 * t + 2] = std::numeric_limits<int>::max();
    b[4 * t + 1] = b[4 * t + 3] = -1;
  }
  const int nc = cons.size();
  const int c0 = static_cast<int>(static_cast<long>(nc) * tid / nt), c1 = static_cast<int>(static_cast<long>(nc) * (tid + 1) / nt);
  for (int c = c0; c < c1; ++c) {
    const ContactConstraint& k = cons[c];
    const int rmin = k.tangent_row >= 0 ? std::min(k.normal_row, k.tangent_row) : k.normal_row;
    const int rmax = std::max(k.normal_row, k.tangent_row);
    const int kind = k.body_a >= 0 && k.body_b >= 0 ? 2 : 0;
    for (const int body : {k.body_a, k.body_b}) {
      if (body < 0) continue;
      const int t = block_of(begin.data(), nt, body);
      b[4 * t + kind] = std::min(b[4 * t + kind], rmin);
      b[4 * t + kind + 1] = std::max(b[4 * t + kind + 1], rmax);
    }
  }
}

/// Part tid of nt of scaled_transpose_product's second phase, after every part's
/// transpose_bounds: block tid's columns summed over its rows in ascending order, from 0.
void transpose_block(const LcpProblem& p, const Eigen::VectorXd& lambda, Eigen::VectorXd& du, int tid, int nt,
                     const int* bounds, bool skip_zero) {
  const int ncols = static_cast<int>(p.J.cols());
  const int bodies = (ncols + 2) / 3;
  const BlockRowRanges r = block_row_ranges(bounds, nt, tid);
  const int col0 = 3 * block_begin(bodies, tid, nt), col1 = std::min(ncols, 3 * block_begin(bodies, tid + 1, nt));
  double* out = du.data();
  for (int c = col0; c < col1; ++c) out[c] = 0.0;
  if (r.lo1 <= r.hi1) transpose_rows(p, lambda.data(), r.lo1, r.hi1 + 1, col0, col1, out, skip_zero);
  if (r.lo2 <= r.hi2) transpose_rows(p, lambda.data(), r.lo2, r.hi2 + 1, col0, col1, out, skip_zero);
  const double* im = p.inv_mass.data();
  const double dt = p.dt;
  for (int c = col0; c < col1; ++c) out[c] = im[c] * out[c] * dt;
}

/// scaled_transpose_product on `threads` threads (> 1) of the calling thread's team.
void scaled_transpose_parts(const LcpProblem& p, const Eigen::VectorXd& lambda, int threads, Eigen::VectorXd& du,
                            bool skip_zero) {
  const int nt = threads;  // blocks (a row range can reach several); a present member takes an absent one's
  du.resize(p.J.cols());
  std::vector<int> bounds(static_cast<size_t>(4 * nt * nt));
  WorkTeam& team = calling_thread_team();
  team.for_parts(threads, nt, [&](int t) { transpose_bounds(p, t, nt, bounds.data()); });
  team.for_parts(threads, nt, [&](int t) { transpose_block(p, lambda, du, t, nt, bounds.data(), skip_zero); });
}

}  // namespace

void scaled_transpose_product(const LcpProblem& p, const Eigen::VectorXd& lambda, int threads, Eigen::VectorXd& du,
                              bool skip_zero) {
  if (threads <= 1) {
    du.setZero(p.J.cols());
    transpose_rows(p, lambda.data(), 0, p.rows(), 0, static_cast<int>(p.J.cols()), du.data(), skip_zero);
    const double* im = p.inv_mass.data();
    double* out = du.data();
    const double dt = p.dt;
    for (int c = 0; c < du.size(); ++c) out[c] = im[c] * out[c] * dt;
    return;
  }
  scaled_transpose_parts(p, lambda, threads, du, skip_zero);
}

double natural_residual(const LcpProblem& p, const Eigen::VectorXd& lambda, int threads, Eigen::VectorXd& du,
                        bool& all_finite, bool skip_zero) {
  const int n = p.rows(), nc = p.constraints.size();
  // By contact when the contacts own the rows (the solver's case: no per-row bound lookup).
  const bool by_contact = nc > 0 && p.constraints.rows() == n;
  constexpr int kContactChunk = 256;  // contacts (or rows) per work item of the threaded loop
  double r = 0.0;
  bool nan = false, nonfinite = false;
  if (threads <= 1) {  // (no parallel region: libgomp allocates a team even for a serial one)
    scaled_transpose_product(p, lambda, 1, du, skip_zero);
    if (by_contact)
      contact_errors(p, lambda.data(), du.data(), 0, nc, r, nan, nonfinite, skip_zero);
    else
      row_errors(p, lambda, du.data(), 0, n, r, nan, nonfinite);
    all_finite = !nonfinite;
    return nan ? std::numeric_limits<double>::infinity() : r;
  }
  // Δu on the calling thread: the blocked product reads every row reaching a block once per
  // block and filters entries by column, more work than the serial scatter, so only the errors
  // are split.
  scaled_transpose_product(p, lambda, 1, du, skip_zero);
  // The errors by chunks; max and or combine the chunks' in any order alike.
  const int items = by_contact ? nc : n;
  const int chunks = (items + kContactChunk - 1) / kContactChunk;
  struct alignas(64) Part {
    double r = 0.0;
    bool nan = false, nonfinite = false;
  };
  std::vector<Part> parts(static_cast<size_t>(chunks));
  calling_thread_team().for_parts(threads, chunks, [&](int k) {
    Part& e = parts[static_cast<size_t>(k)];
    const int i = k * kContactChunk, i1 = std::min(items, i + kContactChunk);
    if (by_contact)
      contact_errors(p, lambda.data(), du.data(), i, i1, e.r, e.nan, e.nonfinite, skip_zero);
    else
      row_errors(p, lambda, du.data(), i, i1, e.r, e.nan, e.nonfinite);
  });
  for (const Part& e : parts) {
    r = std::max(r, e.r);
    nan = nan || e.nan;
    nonfinite = nonfinite || e.nonfinite;
  }
  all_finite = !nonfinite;
  return nan ? std::numeric_limits<double>::infinity() : r;
}

}  // namespace dc::colored
