#include "dc/engine/broad_phase.hpp"

#include <algorithm>
#include <span>
#include <cmath>

#include "dc/core/error.hpp"
#include "world/parts/step_parts.hpp"

namespace dc {

void UniformGridBroadPhase::find_pairs(const std::vector<Vec2>& centres,
                                       const std::vector<double>& reach,
                                       std::vector<std::pair<int, int>>& pairs, int threads) {
  pairs.clear();
  pair_tests_ = 0;
  const int n = static_cast<int>(centres.size());
  if (n < 2) return;
  if (static_cast<int>(reach.size()) != n)
    throw InvalidArgument("UniformGridBroadPhase: reach must have one entry per body");
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(centres[k].x) || !std::isfinite(centres[k].y) || !std::isfinite(reach[k]))
      throw InvalidArgument("UniformGridBroadPhase: body " + std::to_string(k) +
                            " has a non-finite position or radius");
  find(
      n, [&](int k) { return Vec2{centres[k].x - reach[k], centres[k].y - reach[k]}; },
      [&](int k) { return Vec2{centres[k].x + reach[k], centres[k].y + reach[k]}; },
      [&](int k) { return 2 * reach[k]; }, pairs, threads);
}

void UniformGridBroadPhase::find_box_pairs(const std::vector<Vec2>& lo, const std::vector<Vec2>& hi,
                                           std::vector<std::pair<int, int>>& pairs) {
  pairs.clear();
  pair_tests_ = 0;
  const int n = static_cast<int>(lo.size());
  if (n < 2) return;
  if (static_cast<int>(hi.size()) != n)
    throw InvalidArgument("UniformGridBroadPhase: need one upper corner per box");
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(lo[k].x) || !std::isfinite(lo[k].y) || !std::isfinite(hi[k].x) || !std::isfinite(hi[k].y))
      throw InvalidArgument("UniformGridBroadPhase: body " + std::to_string(k) + " has a non-finite bounding box");
  find(
      n, [&](int k) { return lo[k]; }, [&](int k) { return hi[k]; },
      [&](int k) { return std::max(hi[k].x - lo[k].x, hi[k].y - lo[k].y); }, pairs);
}

template <class Lo, class Hi, class Extent>
void UniformGridBroadPhase::find(int n, const Lo& lo, const Hi& hi, const Extent& extent,
                                 std::vector<std::pair<int, int>>& pairs, int threads) {
  // Grid extent: bounding box of all boxes; cell = largest box extent (≥ tiny > 0). By jobs of
  // bodies, combined in job order (each minimum and maximum is the first of its value in body
  // order, as one pass finds it).
  const int body_jobs = parts_for(threads, n, 2, 4096);
  job_bounds_.assign(static_cast<size_t>(5 * body_jobs), 0.0);
  run_parts(threads, body_jobs, [&](int p) {
    double b[5] = {INFINITY, INFINITY, -INFINITY, -INFINITY, 0};  // xmin, ymin, xmax, ymax, cell
    for (int k = static_cast<int>(part_begin(n, body_jobs, p)); k < part_begin(n, body_jobs, p + 1); ++k) {
      const Vec2 l = lo(k), h = hi(k);
      b[0] = std::min(b[0], l.x);
      b[1] = std::min(b[1], l.y);
      b[2] = std::max(b[2], h.x);
      b[3] = std::max(b[3], h.y);
      b[4] = std::max(b[4], extent(k));
    }
    std::copy(b, b + 5, job_bounds_.begin() + 5 * p);
  });
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY, cell = 0;
  for (int p = 0; p < body_jobs; ++p) {
    const double* b = job_bounds_.data() + 5 * p;
    xmin = std::min(xmin, b[0]);
    ymin = std::min(ymin, b[1]);
    xmax = std::max(xmax, b[2]);
    ymax = std::max(ymax, b[3]);
    cell = std::max(cell, b[4]);
  }
  // A hair above the largest extent, so that rounding in the cell index below can never put
  // the lower corners of two overlapping boxes two cells apart.
  cell = std::max(cell * (1 + 1e-9), 1e-12 * std::max({1.0, xmax - xmin, ymax - ymin}));
  // Cap the number of cells at ~4n so memory stays linear even for sparse, spread scenes.
  double nxd = std::floor((xmax - xmin) / cell) + 1, nyd = std::floor((ymax - ymin) / cell) + 1;
  while (nxd * nyd > 4.0 * n + 16) {
    cell *= 2;
    nxd = std::floor((xmax - xmin) / cell) + 1;
    nyd = std::floor((ymax - ymin) / cell) + 1;
  }
  const long long nx = static_cast<long long>(nxd), ny = static_cast<long long>(nyd);
  // Cell of a coordinate: monotone (clamped to the grid), so boxes whose lower corners are at
  // most one cell apart land in the same or neighbouring cells.
  const double inv_cell = 1.0 / cell;
  auto cx = [&](double x) { return std::clamp<long long>(static_cast<long long>((x - xmin) * inv_cell), 0, nx - 1); };
  auto cy = [&](double y) { return std::clamp<long long>(static_cast<long long>((y - ymin) * inv_cell), 0, ny - 1); };

  // One entry per body, in the cell of its box's lower-left corner (a counting sort by cell,
  // the entries carrying their boxes so the pair loop reads memory in cell order instead of
  // gathering boxes by body index, which is random in space). The cell is at least every
  // box's extent, so two overlapping boxes have lower corners at most one cell apart in x
  // and in y (the clamp is monotone and only shortens distances): the pairs are found among
  // a cell and its neighbours, each neighbouring pair of cells visited once (the half
  // stencil: same cell later entries, right; then upper-left, upper, upper-right). Cells are
  // row-major, so a cell and its right neighbour, and the three cells above, are each one
  // contiguous run of entries. A body is not entered in every cell its box touches because that
  // multiplies the entries and needs a corner rule to skip duplicate pairs.
  // By jobs of bodies: each job counts its bodies per cell (and per range of cells, the
  // ranges cell_offsets works on), then files them at its offsets, so a cell holds its bodies
  // in body order whatever the thread count.
  cell_of_body_.resize(static_cast<size_t>(n));
  const long long ncell = nx * ny;
  const int fill_jobs = parts_for(threads, n, 1, 4096);
  const int ranges = std::min(fill_jobs, kMaxRanges);
  long long range_begin[kMaxRanges + 1];
  for (int r = 0; r <= ranges; ++r) range_begin[r] = cell_range_begin(ncell, ranges, r);
  cell_count_.resize(static_cast<size_t>(fill_jobs * ncell));
  range_count_.assign(static_cast<size_t>(fill_jobs * ranges), 0);
  run_parts(threads, fill_jobs, [&](int p) {
    int* count = cell_count_.data() + p * ncell;
    std::fill(count, count + ncell, 0);
    int in_range[kMaxRanges] = {};
    const int k0 = static_cast<int>(part_begin(n, fill_jobs, p)), k1 = static_cast<int>(part_begin(n, fill_jobs, p + 1));
    for (int k = k0; k < k1; ++k) {
      const Vec2 l = lo(k);
      const long long c = cy(l.y) * nx + cx(l.x);
      cell_of_body_[static_cast<size_t>(k)] = c;
      ++count[c];
      int r = 0;
      for (int s = 1; s < ranges; ++s) r += static_cast<int>(c >= range_begin[s]);
      in_range[r] += ranges > 1 ? 1 : 0;
    }
    if (ranges == 1) in_range[0] = k1 - k0;
    std::copy(in_range, in_range + ranges, range_count_.begin() + static_cast<std::ptrdiff_t>(p) * ranges);
  });
  cell_offsets(ncell, fill_jobs, ranges, threads);
  entries_.resize(static_cast<size_t>(n));
  run_parts(threads, fill_jobs, [&](int p) {
    int* at = cell_count_.data() + p * ncell;
    for (int k = static_cast<int>(part_begin(n, fill_jobs, p)); k < part_begin(n, fill_jobs, p + 1); ++k) {
      const Vec2 l = lo(k), h = hi(k);
      entries_[static_cast<size_t>(at[cell_of_body_[static_cast<size_t>(k)]]++)] = {l.x, l.y, h.x, h.y, k};
    }
  });

  // The pair tests by rows of cells, one list per job (rows [begin, end) of the grid).
  const int jobs = parts_for(threads, static_cast<long>(ny), 8, 4);
  if (by_body_.size() < static_cast<size_t>(jobs)) by_body_.resize(static_cast<size_t>(jobs));
  // Any job may find nearly every pair (a settled pile fills a few rows of cells, a falling one
  // others): each job's list holds, with headroom for the tested pairs written past the kept
  // ones, as many as the most pairs a run has found, so that a run which finds no more pairs
  // than an earlier one allocates nothing, however they fall on the jobs.
  // A list that grows takes at least half again its size, so a growing pile reallocates it rarely.
  const std::size_t room = most_found_ + most_found_ / 4 + 64;
  for (auto& list : std::span(by_body_).first(static_cast<size_t>(jobs)))
    if (list.size() < room) list.resize(std::max(room, list.size() + list.size() / 2));
  tests_.assign(static_cast<size_t>(jobs), 0);
  found_.assign(static_cast<size_t>(jobs), 0);
  run_parts(threads, jobs, [&](int p) {
    tests_[static_cast<size_t>(p)] = test_rows(part_begin(static_cast<long>(ny), jobs, p),
                                               part_begin(static_cast<long>(ny), jobs, p + 1), nx, ny,
                                               by_body_[static_cast<size_t>(p)], found_[static_cast<size_t>(p)]);
  });
  for (const std::size_t t : tests_) pair_tests_ += t;
  std::size_t found = 0;
  for (const std::size_t f : found_) found += f;
  most_found_ = std::max(most_found_, found);
  sort_pairs(n, pairs, jobs, threads);
}

std::size_t UniformGridBroadPhase::test_rows(long long row_begin, long long row_end, long long nx, long long ny,
                                             std::vector<std::pair<int, int>>& out, std::size_t& found) const {
  // The overlap test's outcome is added, not branched on: every tested pair is written after
  // the kept ones and kept only when the boxes overlap. Which neighbours of a cell overlap
  // follows no pattern a branch predictor can learn once the scene outgrows its tables (body
  // indices are unordered within a cell), and a mispredicted branch per test would cost more
  // than the test. `out` is capacity; its first `found` entries are the pairs.
  found = 0;
  std::size_t tests = 0;
  auto test_run = [&](const Entry& a, int from, int to) {
    if (from >= to) return;
    const auto run = static_cast<std::size_t>(to - from);
    if (found + run > out.size()) out.resize(std::max(2 * out.size(), found + run + 64));
    std::pair<int, int>* const dst = out.data();
    for (int q = from; q < to; ++q) {
      const Entry& b = entries_[static_cast<size_t>(q)];
      const bool apart_x = std::max(a.xlo, b.xlo) > std::min(a.xhi, b.xhi);
      const bool apart_y = std::max(a.ylo, b.ylo) > std::min(a.yhi, b.yhi);
      // (min, max) of the two bodies without a branch: the xor of both, masked when b < a.
      const int swap = (a.body ^ b.body) & -static_cast<int>(b.body < a.body);
      dst[found] = {a.body ^ swap, b.body ^ swap};
      found += static_cast<std::size_t>(!(apart_x | apart_y));
    }
    tests += run;
  };
  auto start = [&](long long c) { return cell_start_[static_cast<size_t>(c)]; };
  for (long long j = row_begin; j < row_end; ++j)
    for (long long i = 0; i < nx; ++i) {
      const long long c = j * nx + i;
      const int s = start(c), e = start(c + 1);
      if (s == e) continue;
      const int right_end = i + 1 < nx ? start(c + 2) : e;  // this cell's later entries, then the right cell
      const bool above = j + 1 < ny;
      const int up_begin = above ? start(c + nx - (i > 0 ? 1 : 0)) : 0;
      const int up_end = above ? start(c + nx + (i + 1 < nx ? 2 : 1)) : 0;
      for (int p = s; p < e; ++p) {
        const Entry& a = entries_[static_cast<size_t>(p)];
        test_run(a, p + 1, right_end);
        if (above) test_run(a, up_begin, up_end);
      }
    }
  return tests;
}

}  // namespace dc
