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
//
// Kept candidates (broad_phase_kept.cpp): each body k also has a fat box F_k, its box when F_k
// was set enlarged by a margin m on every side, and the broad phase keeps between calls the
// sorted list C of the pairs whose fat boxes overlap. While every body's box B_k stays inside
// F_k, two overlapping boxes have overlapping fat boxes, so the pairs are C filtered by the same
// box test a fresh search makes, in C's sorted order: the same pairs, bit for bit, without a
// grid search. A body whose box left F_k (it "escaped") gets a new fat box, is moved in a kept
// grid of fat boxes, and only its pairs of C are found again, by a query of the 3 × 3 cells
// around it; when many bodies escape, a box outgrows the grid's cell, or the body count changes,
// the grid and C are rebuilt by the grid search over fat boxes. The check is by body index
// only, so renumbered bodies are caught like moved ones.
#include <utility>
#include <vector>

#include "dc/engine/body_state.hpp"

namespace dc {

/// Options of the broad phase's kept candidates (broad_phase.hpp).
struct BroadPhaseDef {
  /// Fat-box margin m as a fraction of the largest box extent (max over k of the larger side of
  /// B_k) at the last rebuild: m = margin · extent [m]. A larger margin lets bodies move further
  /// before they escape, and hands the filter more candidates whose boxes do not overlap. 0 keeps
  /// no candidates: every call searches the grid afresh.
  double margin = 0.3;
  /// A rebuild instead of queries when more than this fraction of the bodies escaped at once
  /// (a query of the 3 × 3 cells per escaped body costs more than a body's share of a rebuild).
  double max_escaped = 0.5;
};

class UniformGridBroadPhase {
 public:
  explicit UniformGridBroadPhase(BroadPhaseDef def = {});

  /// Candidate pairs whose boxes (centre ± reach) overlap. `reach` has one entry per body.
  void find_pairs(const std::vector<Vec2>& centres, const std::vector<double>& reach,
                  std::vector<std::pair<int, int>>& pairs, int threads = 1);

  /// Candidate pairs whose axis-aligned boxes [lo_k, hi_k] overlap: the shapes' real boxes
  /// (rotation and speculative reach included by the caller). Same grid, same guarantees.
  void find_box_pairs(const std::vector<Vec2>& lo, const std::vector<Vec2>& hi,
                      std::vector<std::pair<int, int>>& pairs);

  /// Box-overlap tests the last find_pairs() or find_box_pairs() performed: the broad phase's
  /// work, a load-independent measure of its cost (linear in n for bodies of similar size). It
  /// counts every test of two boxes: of the grid search (fat boxes on a rebuild, true boxes
  /// without kept candidates), of the escaped bodies' queries, and of the filter of the kept
  /// candidates (one per candidate). The escape check (one containment test per body) is not
  /// counted.
  [[nodiscard]] std::size_t last_pair_tests() const { return pair_tests_; }
  /// How the last call found its pairs: by the grid search of every body (a rebuild, or no kept
  /// candidates), or from the kept candidates after its `last_escaped()` escaped bodies were
  /// queried (0: the filter alone). last_escaped() is n when there were no kept candidates.
  [[nodiscard]] bool last_rebuilt() const { return rebuilt_; }
  [[nodiscard]] int last_escaped() const { return escaped_count_; }
  [[nodiscard]] const BroadPhaseDef& def() const { return def_; }

 private:
  /// The grid search over boxes given by accessors (the circle and the box entry points).
  template <class Lo, class Hi, class Extent>
  void find(int n, const Lo& lo, const Hi& hi, const Extent& extent, std::vector<std::pair<int, int>>& pairs,
            int threads = 1);
  /// The pairs of boxes given by accessors: from the kept candidates when they are still exact,
  /// else by a fresh search (broad_phase_kept.cpp).
  template <class Lo, class Hi, class Extent>
  void find_kept(int n, const Lo& lo, const Hi& hi, const Extent& extent, std::vector<std::pair<int, int>>& pairs,
                 int threads);
  /// The grid search over fat boxes into cand_, and the kept grid of fat boxes (head_, next_, prev_).
  void rebuild_kept(int n, int threads);
  /// The escaped bodies (escaped_) moved in the kept grid and their pairs of cand_ found again;
  /// false (nothing changed) when a rebuild is needed instead.
  bool requery_escaped();
  /// pairs = the candidates whose true boxes (tlo_, thi_) overlap, in order; its tests.
  std::size_t filter_candidates(std::vector<std::pair<int, int>>& pairs, int threads);
  /// The kept grid's cell of a lower corner (clamped in floating point, so far boxes stay finite).
  [[nodiscard]] long long kept_cell(double x, double y) const;
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
  BroadPhaseDef def_;
  std::size_t pair_tests_ = 0;
  bool rebuilt_ = true;
  int escaped_count_ = 0;
  /// The last grid search's grid: lower corner, cell size and cells per row and column [m].
  double grid_x0_ = 0, grid_y0_ = 0, grid_cell_ = 1;
  long long grid_nx_ = 1, grid_ny_ = 1;
  // Kept candidates: the bodies' true and fat boxes (x lo, y lo, x hi, y hi each), the pairs of
  // overlapping fat boxes (sorted), the kept grid of fat boxes (a doubly linked list per cell,
  // -1 ends), the escaped bodies and per-body marks.
  int kept_n_ = -1;  // bodies of the kept candidates; -1: none
  double margin_ = 0;  // m [m]
  std::vector<double> tbox_, fbox_;
  std::vector<std::pair<int, int>> cand_, cand_next_, requeried_;
  std::vector<int> head_, next_, prev_, escaped_;
  std::vector<long long> kept_cell_of_;
  std::vector<char> is_escaped_;
  std::vector<std::vector<int>> part_escaped_;                  // per job of the escape check
  std::vector<std::vector<std::pair<int, int>>> part_pairs_;   // per job of the filter
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
