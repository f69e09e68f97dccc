#pragma once
// Broad phase: a uniform grid over the bodies' bounding boxes. Each body k covers the
// square of half-extent reach_k = r_k + s_k around its centre (s_k is its speculative
// reach, see narrow_phase.hpp). The cell size is the largest box extent; each body is filed
// once, in the cell of its box's lower-left corner, and its partners are among the bodies of
// that cell and its 8 neighbours, so finding all overlapping pairs costs O(n) for bodies of
// similar size (a scene mixing very different radii degrades towards O(n·k) where k is
// the number of small bodies per large cell — documented in docs/engine.md).
//
// Pairs are reported once each, as (i < j), sorted, so the result does not depend on the
// order of insertion, the grid layout or the threads (`threads` > 1: the pair tests of rows of
// cells run as parallel jobs; World::step).
#include <utility>
#include <vector>

#include "dc/engine/body_state.hpp"

namespace dc {

class UniformGridBroadPhase {
 public:
  /// Candidate pairs whose boxes (centre ± reach) overlap. `reach` has one entry per body.
  void find_pairs(const std::vector<Vec2>& centres, const std::vector<double>& reach,
                  std::vector<std::pair<int, int>>& pairs, int threads = 1);

  /// Candidate pairs whose axis-aligned boxes [lo_k, hi_k] overlap: the shapes' real boxes
  /// (rotation and speculative reach included by the caller). Same grid, same guarantees.
  void find_box_pairs(const std::vector<Vec2>& lo, const std::vector<Vec2>& hi,
                      std::vector<std::pair<int, int>>& pairs);

  /// Box-overlap tests the last find_pairs() performed: the broad phase's work, a
  /// load-independent measure of its cost (linear in n for bodies of similar size).
  [[nodiscard]] std::size_t last_pair_tests() const { return pair_tests_; }

 private:
  /// The grid search over boxes given by accessors (the circle and the box entry points).
  template <class Lo, class Hi, class Extent>
  void find(int n, const Lo& lo, const Hi& hi, const Extent& extent, std::vector<std::pair<int, int>>& pairs,
            int threads = 1);
  /// The pairs of cell rows [row_begin, row_end) into the first `found` entries of `out` (used as
  /// capacity); the box-overlap tests it made.
  std::size_t test_rows(long long row_begin, long long row_end, long long nx, long long ny,
                        std::vector<std::pair<int, int>>& out, std::size_t& found) const;
  /// `pairs` sorted from the jobs' lists (broad_phase_sorts.cpp): on `threads` threads, each
  /// sorting the pairs of one range of first bodies by counting sorts (second, then first body).
  void sort_pairs(int n, std::vector<std::pair<int, int>>& pairs, int jobs, int threads);
  /// The next sort's ranges of first bodies (sort_bound_): equal shares of this sort's `total` pairs.
  void share_bounds(int n, std::size_t total, int sorts);
  /// The cell fill's offsets (broad_phase_sorts.cpp): from fill_jobs rows of per-cell counts
  /// (cell_count_, row p: the bodies of body job p in each cell) and the bodies of each job in
  /// each of `ranges` cell ranges (range_count_[p·ranges + r]), each count replaced by the first
  /// entry of its job's bodies in that cell, and cell_start_ (ncell + 1 entries) set; on
  /// `threads` threads, one range of cells each.
  void cell_offsets(long long ncell, int fill_jobs, int ranges, int threads);
  /// Cell ranges of cell_offsets: range r holds cells [cell_range_begin(r), cell_range_begin(r + 1)).
  [[nodiscard]] static long long cell_range_begin(long long ncell, int ranges, int r) { return ncell * r / ranges; }
  static constexpr int kMaxRanges = 8;  // cell ranges of cell_offsets, at most
  std::size_t pair_tests_ = 0;
  /// A body's box in one cell, in cell order.
  struct Entry {
    double xlo, ylo, xhi, yhi;
    int body;
  };
  // Reused buffers (no allocation in steady state).
  std::vector<int> cell_start_;
  std::vector<long long> cell_of_body_;
  std::vector<double> job_bounds_;  // per job of bodies: xmin, ymin, xmax, ymax, largest extent
  std::vector<Entry> entries_;
  std::vector<std::vector<std::pair<int, int>>> by_body_;  // per job of the pair tests (capacity)
  std::vector<std::size_t> tests_, found_;                  // per job: tests made, pairs kept
  std::size_t most_found_ = 0;                               // the most pairs one run kept (all jobs)
  std::vector<int> cell_count_;                              // per fill job and cell (cell_offsets)
  std::vector<int> range_count_;                             // per fill job and cell range
  /// A sort job's buffers: its pairs as gathered, sorted by second body, and a histogram.
  struct SortJob {
    std::vector<std::pair<int, int>> mine, by_second;
    std::vector<int> start;
  };
  std::vector<SortJob> sort_jobs_;
  std::vector<int> sort_bound_, bound_scratch_;  // the sort jobs' ranges of first bodies (sorts + 1 bounds)
};

}  // namespace dc
