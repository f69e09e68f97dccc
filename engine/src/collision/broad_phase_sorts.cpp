// The broad phase's two counting sorts on threads (broad_phase.hpp): the cell fill's offsets
// and the sorted pair list. Each writes what only one job owns, so the entries and the pairs are
// the same bits on every thread count.
#include <algorithm>

#include "dc/engine/broad_phase.hpp"
#include "world/parts/step_parts.hpp"

namespace dc {

namespace {

/// Room for n elements in v, grown to 1.5·n when short of it: a pair list that grows step by
/// step while a pile compacts reallocates a few times, not at every step (vector::assign
/// allocates exactly n, and resize max(n, 2·size) with size = capacity after a copy).
template <class T>
void reserve_with_headroom(std::vector<T>& v, std::size_t n) {
  if (v.capacity() < n) v.reserve(n + n / 2);
}

}  // namespace

void UniformGridBroadPhase::cell_offsets(long long ncell, int fill_jobs, int ranges, int threads) {
  // Entries are in cell order, and inside a cell in body order, which is job order: the first
  // entry of job p's bodies in cell c is the number of bodies in cells before c plus those of
  // jobs before p in c. A range of cells starts after every body of the ranges before it.
  int base[kMaxRanges + 1] = {};
  for (int r = 0; r < ranges; ++r) {
    int in = 0;
    for (int p = 0; p < fill_jobs; ++p) in += range_count_[static_cast<size_t>(p * ranges + r)];
    base[r + 1] = base[r] + in;
  }
  cell_start_.resize(static_cast<size_t>(ncell + 1));
  cell_start_[static_cast<size_t>(ncell)] = base[ranges];
  if (fill_jobs == 1) {  // one job: a prefix sum, its offsets the cells' starts
    int at = 0;
    int* count = cell_count_.data();
    int* start = cell_start_.data();
    for (long long c = 0; c < ncell; ++c) {
      start[c] = at;
      const int bodies = count[c];
      count[c] = at;
      at += bodies;
    }
    return;
  }
  run_parts(threads, ranges, [&](int r) {
    int at = base[r];
    for (long long c = cell_range_begin(ncell, ranges, r); c < cell_range_begin(ncell, ranges, r + 1); ++c) {
      cell_start_[static_cast<size_t>(c)] = at;
      for (int p = 0; p < fill_jobs; ++p) {
        int& count = cell_count_[static_cast<size_t>(p * ncell + c)];
        const int bodies = count;
        count = at;
        at += bodies;
      }
    }
  });
}

void UniformGridBroadPhase::sort_pairs(int n, std::vector<std::pair<int, int>>& pairs, int jobs, int threads) {
  // Sorted output in linear time. Sort job t owns the pairs whose first body is in its range
  // [lo, hi) of bodies: it gathers them from the pair tests' lists (and counts the pairs of
  // earlier ranges: its place in the output), then sorts them by two stable counting sorts, by
  // the second body and then by the first. Every pair is distinct, so the order is the same
  // whatever order the lists held them in. Branch-free gather and scatters: which pairs a job
  // keeps, and a body's few partners, come in no order a branch predictor could learn.
  std::size_t total = 0;
  for (int p = 0; p < jobs; ++p) total += found_[static_cast<size_t>(p)];
  reserve_with_headroom(pairs, total);  // (cleared by the caller)
  pairs.resize(total);
  const int sorts = parts_for(threads, n, 1, 4096);
  if (sort_jobs_.size() < static_cast<size_t>(sorts)) sort_jobs_.resize(static_cast<size_t>(sorts));
  // The ranges: equal shares of the last sort's pairs (by first body, kept from its histograms)
  // when it had as many jobs over as many bodies, else equal ranges of bodies. Any ranges give
  // the same pairs; shares balance the jobs whatever the order of the bodies.
  const bool shares = sort_bound_.size() == static_cast<size_t>(sorts) + 1 && sort_bound_.back() == n;
  if (!shares) {
    sort_bound_.resize(static_cast<size_t>(sorts) + 1);
    for (int t = 0; t <= sorts; ++t) sort_bound_[static_cast<size_t>(t)] = static_cast<int>(part_begin(n, sorts, t));
  }
  run_parts(threads, sorts, [&](int t) {
    const int lo = sort_bound_[static_cast<size_t>(t)], hi = sort_bound_[static_cast<size_t>(t) + 1];
    SortJob& job = sort_jobs_[static_cast<size_t>(t)];
    reserve_with_headroom(job.mine, total);
    if (job.mine.size() < total) job.mine.resize(total);
    std::pair<int, int>* mine = job.mine.data();
    std::size_t kept = 0, before = 0;
    for (int p = 0; p < jobs && sorts == 1; ++p) {  // one job keeps every pair
      const std::pair<int, int>* list = by_body_[static_cast<size_t>(p)].data();
      mine = std::copy(list, list + found_[static_cast<size_t>(p)], mine);
    }
    if (sorts == 1) kept = total, mine = job.mine.data();
    for (int p = 0; p < jobs && sorts > 1; ++p) {
      const std::pair<int, int>* list = by_body_[static_cast<size_t>(p)].data();
      for (std::size_t i = 0; i < found_[static_cast<size_t>(p)]; ++i) {
        const std::pair<int, int> pair = list[i];
        mine[kept] = pair;
        kept += static_cast<std::size_t>((pair.first >= lo) & (pair.first < hi));
        before += static_cast<std::size_t>(pair.first < lo);
      }
    }
    reserve_with_headroom(job.by_second, kept);
    if (job.by_second.size() < kept) job.by_second.resize(kept);
    // Keys key(pair) − lo in [0, keys) (lo and kept as locals: the histogram's int stores could
    // alias a captured int).
    const auto counting_sort = [&](const std::pair<int, int>* in, std::pair<int, int>* out, int keys, auto key) {
      const int first = lo;
      const std::size_t m = kept;
      reserve_with_headroom(job.start, static_cast<size_t>(keys) + 1);
      job.start.assign(static_cast<size_t>(keys) + 1, 0);
      int* start = job.start.data();
      for (std::size_t i = 0; i < m; ++i) ++start[key(in[i]) - first + 1];
      for (int k = 0; k < keys; ++k) start[k + 1] += start[k];
      for (std::size_t i = 0; i < m; ++i) out[start[key(in[i]) - first]++] = in[i];
    };
    counting_sort(mine, job.by_second.data(), n - lo, [](const std::pair<int, int>& q) { return q.second; });
    counting_sort(job.by_second.data(), pairs.data() + before, hi - lo,
                  [](const std::pair<int, int>& q) { return q.first; });
  });
  if (sorts > 1) share_bounds(n, total, sorts);
}

void UniformGridBroadPhase::share_bounds(int n, std::size_t total, int sorts) {
  // After the sort by first body, job t's start[j] is the number of its pairs whose first body
  // is at most lo_t + j; bound s is the first body b with at least total·s/sorts pairs before it.
  std::vector<int>& next = bound_scratch_;
  next.assign(static_cast<size_t>(sorts) + 1, n);
  next[0] = 0;
  std::size_t before = 0;  // pairs of the jobs before t
  int s = 1;
  for (int t = 0; t < sorts && s < sorts; ++t) {
    const int lo = sort_bound_[static_cast<size_t>(t)], hi = sort_bound_[static_cast<size_t>(t) + 1];
    const int* start = sort_jobs_[static_cast<size_t>(t)].start.data();
    for (; s < sorts; ++s) {
      const std::size_t target = total * static_cast<std::size_t>(s) / static_cast<std::size_t>(sorts);
      if (hi == lo || before + static_cast<std::size_t>(start[hi - lo - 1]) < target) break;
      // The first j with before + start[j] ≥ target: bodies lo … lo + j hold the target pair.
      const int j = static_cast<int>(
          std::lower_bound(start, start + (hi - lo), static_cast<int>(target - before)) - start);
      next[static_cast<size_t>(s)] = std::max(next[static_cast<size_t>(s) - 1], lo + j + 1);
    }
    if (hi > lo) before += static_cast<std::size_t>(start[hi - lo - 1]);
  }
  for (; s < sorts; ++s) next[static_cast<size_t>(s)] = n;
  sort_bound_.swap(next);
}

}  // namespace dc
