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
  /// `pairs` sorted from the jobs' lists (stable counting sorts by second, then first body).
  void sort_pairs(int n, std::vector<std::pair<int, int>>& pairs, int jobs);
  std::size_t pair_tests_ = 0;
  /// A body's box in one cell, in cell order.
  struct Entry {
    double xlo, ylo, xhi, yhi;
    int body;
  };
  // Reused buffers (no allocation in steady state).
  std::vector<int> cell_start_, fill_, first_start_;
  std::vector<long long> cell_of_body_;
  std::vector<double> job_bounds_;  // per job of bodies: xmin, ymin, xmax, ymax, largest extent
  std::vector<Entry> entries_;
  std::vector<std::vector<std::pair<int, int>>> by_body_;  // per job of the pair tests (capacity)
  std::vector<std::size_t> tests_, found_;                  // per job: tests made, pairs kept
  std::vector<std::pair<int, int>> by_second_;              // the pairs sorted by second body
};

}  // namespace dc
