#pragma once
// Candidate pairs of the circle narrow phase kept across steps (a Verlet list). At a rebuild
// the broad phase runs with every reach R_k = r_k + s_k grown by a skin σ, and the pairs whose
// centres are closer than R_i + R_j + 2σ are kept, with the centres x⁰_k and reaches R⁰_k they
// were found at. Body k's anchor is x⁰_k + D, where D is a shift common to every body (zero at a
// rebuild). While every body satisfies |x_k − x⁰_k − D| + max(0, R_k − R⁰_k) ≤ 0.9σ, each pair
// within R_i + R_j now was within R⁰_i + R⁰_j + 1.8σ then (x_i − x_j = x⁰_i − x⁰_j plus the two
// bodies' motions from their anchors, and the shift cancels; the 0.2σ to spare absorbs
// rounding), so the kept list is a superset of the pairs the narrow phase accepts, and its test
// on that list gives the same contacts as a fresh broad phase: the same keys in the same
// (sorted) order, bit for bit. Since D cancels, each step may choose it: the held D, or the
// median motion x_k − x⁰_k of a sample of the bodies when fewer bodies escape with it, so a
// pile falling as one keeps its list. σ is a fixed fraction of the largest reach at the
// rebuild: a settled pile keeps its list for many steps. Where lists expire after a step or
// two (a falling or flowing pile), the broad phase runs without one for a while (pairs()).
// The check is by body index only, so a renumbering of the bodies (the internal order's
// re-sort) or a user's edit is caught like any motion; a change in the body count rebuilds.
//
// Bodies beyond the skin (a grain rolling down a settled pile, part of a pile still falling) do
// not rebuild the list: each such body e is re-anchored (x⁰_e = x_e − D, R⁰_e = R_e), its pairs are
// dropped and found again by the same test, |x⁰_e − x⁰_j| < R⁰_e + R⁰_j + 2σ, against the anchors
// of a kept grid (every anchor filed in a cell; an escaped body moves to its new anchor's cell),
// and merged back in sorted order. The list stays exactly the pairs of anchors within the grown
// reach, so the bound above holds body by body. A patch costs a few cells per escaped body and a
// pass over the list, a rebuild a broad phase of n grown boxes: up to a fixed fraction of the
// bodies escaped in a step are patched (circle_pair_cache.cpp), more rebuild.
#include <cstddef>
#include <utility>
#include <vector>

#include "dc/core/vec2.hpp"
#include "dc/engine/broad_phase.hpp"

namespace dc {

class CirclePairCache {
 public:
  /// A sorted (i < j) superset of the pairs whose centres lie within reach[i] + reach[j] of each
  /// other, from the kept list or from `broad_phase` (rebuilt(): which). The reference stays
  /// valid until the next call.
  const std::vector<std::pair<int, int>>& pairs(const std::vector<Vec2>& centres, const std::vector<double>& reach,
                                                UniformGridBroadPhase& broad_phase, int threads);
  /// Whether the last pairs() ran the broad phase.
  [[nodiscard]] bool rebuilt() const { return rebuilt_; }
  /// Whether the last pairs() served the kept list with escaped bodies re-anchored (not rebuilt).
  [[nodiscard]] bool patched() const { return patched_; }

 private:
  /// The bodies beyond the skin of their anchors into escaped_ (in body order, at most
  /// patch limit + 1 of them per job); false when the sizes changed or one is not finite.
  [[nodiscard]] bool find_escaped(const std::vector<Vec2>& centres, const std::vector<double>& reach,
                                  int threads);
  /// Re-anchors the bodies of escaped_ and replaces their pairs (see the file comment).
  void patch(const std::vector<Vec2>& centres, const std::vector<double>& reach);
  /// The kept pairs without the escaped bodies merged with added_ (sorted) into pairs_.
  void merge_patched();
  /// Files every anchor in a grid of cells (patch() queries it); the grid is kept until a rebuild.
  void build_grid();
  /// The cell of a point, clamped into the grid.
  [[nodiscard]] int cell_of(Vec2 x) const;
  void file(int k, int cell);  ///< body k at the head of the cell's list
  void unfile(int k);          ///< body k out of its cell's list
  void rebuild(const std::vector<Vec2>& centres, const std::vector<double>& reach,
               UniformGridBroadPhase& broad_phase, int threads);
  std::vector<Vec2> centre0_;           ///< x⁰_k [m]
  std::vector<double> reach0_, grown_;  ///< R⁰_k, and R⁰_k + σ for the broad phase [m]
  std::vector<std::pair<int, int>> boxes_, pairs_, merged_, added_;
  /// The median drift x_k − x⁰_k of a sample of the bodies (a candidate shift_).
  [[nodiscard]] Vec2 sample_drift(const std::vector<Vec2>& centres) const;
  std::vector<std::vector<int>> part_escaped_;  ///< per job of find_escaped and frame: its escaped bodies
  std::vector<std::size_t> part_count_;         ///< per job of find_escaped and frame: escaped bodies
  std::vector<int> escaped_;                    ///< the escaped bodies of this step, in body order
  std::vector<char> is_escaped_;                ///< per body: in escaped_ (all 0 between patches)
  // The anchor grid: per cell the first body of a doubly linked list through next_/prev_.
  std::vector<int> head_, next_, prev_, cell_of_;
  Vec2 origin_;                ///< the grid's lower corner [m]
  double cell_ = 1;            ///< a cell's side [m]
  double reach0_max_ = 0;      ///< an upper bound of every R⁰_k [m]
  int cols_ = 1, rows_ = 1;
  bool grid_kept_ = false;     ///< the grid files the current anchors
  double skin_ = 0;  ///< σ [m]
  Vec2 shift_;       ///< D: body k's anchor is x⁰_k + D (centre0_ holds x⁰_k) [m]
  int uses_ = 0;        ///< steps the kept list served after its rebuild
  int plain_run_ = 0;   ///< length of the last run of steps without a list
  int plain_left_ = 0;  ///< steps left in the current run without a list
  bool kept_ = false, rebuilt_ = false, patched_ = false;
};

}  // namespace dc
