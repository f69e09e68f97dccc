#include "dc/engine/circle_pair_cache.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "world/parts/step_parts.hpp"

namespace dc {
namespace {

/// σ ÷ the largest reach at a rebuild: a larger skin keeps the list longer and hands the
/// narrow phase more pairs that are not in contact.
constexpr double kSkinOfReach = 0.2;
/// The motion a body may make before the list is rebuilt, as a fraction of σ (circle_pair_cache.hpp).
constexpr double kMotionOfSkin = 0.9;
/// A list that served fewer steps after its rebuild than this did not pay for its skin: the
/// broad phase then runs plainly (no list) for a number of steps that doubles up to kMaxPlain.
constexpr int kPayingUses = 2;
constexpr int kMaxPlain = 32;
/// Escaped bodies a step patches at most, as a fraction of the bodies (circle_pair_cache.hpp):
/// a patch costs a grid query per escaped body and a pass over the list, where a rebuild files
/// every grown box in the broad phase's grid, tests its neighbours and sorts all the pairs; beyond
/// this fraction the pile is on the move and the list is rebuilt.
constexpr double kPatchedOfBodies = 0.1;
/// Bodies whose motion gives the common drift (sample_drift()): odd, so the median is one of them.
constexpr std::size_t kDriftSamples = 63;
/// The drift is tested as a second frame when it is farther than this fraction of the bound
/// from the held shift.
constexpr double kDriftChange = 0.05;
/// The anchor grid holds at most this many cells per body (its cell grows to fit).
constexpr double kCellsPerBody = 2.0;

/// Room for `size` entries and half as many more when the vector has less: the kept list and its
/// buffers grow while a pile compacts, and growing them a little at a time allocates often.
template <class T>
void reserve_with_headroom(std::vector<T>& v, std::size_t size) {
  if (v.capacity() < size) v.reserve(size + size / 2);
}

/// The escaped bodies a step patches at most among n.
std::size_t patch_limit(std::size_t n) { return static_cast<std::size_t>(kPatchedOfBodies * static_cast<double>(n)); }

}  // namespace

const std::vector<std::pair<int, int>>& CirclePairCache::pairs(const std::vector<Vec2>& centres,
                                                              const std::vector<double>& reach,
                                                              UniformGridBroadPhase& broad_phase, int threads) {
  patched_ = false;
  rebuilt_ = !(kept_ && find_escaped(centres, reach, threads) && escaped_.size() <= patch_limit(centres.size()));
  if (!rebuilt_) {
    if (!escaped_.empty()) {
      patch(centres, reach);
      patched_ = true;
    }
    ++uses_;
    return pairs_;
  }
  if (kept_) {  // the list expired: did it pay?
    plain_run_ = uses_ < kPayingUses ? std::min(kMaxPlain, std::max(1, 2 * plain_run_)) : 0;
    plain_left_ = plain_run_;
    kept_ = false;
  }
  if (plain_left_ > 0) {
    --plain_left_;
    broad_phase.find_pairs(centres, reach, pairs_, threads);
    return pairs_;
  }
  rebuild(centres, reach, broad_phase, threads);
  uses_ = 0;
  return pairs_;
}

Vec2 CirclePairCache::sample_drift(const std::vector<Vec2>& centres) const {
  // The median of each coordinate of x_k − x⁰_k over kDriftSamples bodies spread over the
  // numbering: the common motion of the majority (a pile in free fall moves as one), robust to
  // the minority that moves otherwise (a landed layer, a few fast grains).
  const std::size_t n = centres.size(), m = std::min(n, kDriftSamples);
  std::array<double, kDriftSamples> dx{}, dy{};
  for (std::size_t s = 0; s < m; ++s) {
    const std::size_t k = s * n / m;
    dx[s] = centres[k].x - centre0_[k].x;
    dy[s] = centres[k].y - centre0_[k].y;
  }
  std::nth_element(dx.begin(), dx.begin() + m / 2, dx.begin() + m);
  std::nth_element(dy.begin(), dy.begin() + m / 2, dy.begin() + m);
  return {dx[m / 2], dy[m / 2]};
}

bool CirclePairCache::find_escaped(const std::vector<Vec2>& centres, const std::vector<double>& reach, int threads) {
  escaped_.clear();
  const int n = static_cast<int>(centres.size());
  if (centre0_.size() != centres.size() || reach.size() != centres.size()) return false;
  const double bound = kMotionOfSkin * skin_;
  const std::size_t limit = patch_limit(centres.size());
  // Two frames of the anchors: the one they are held in (shift_) and the sample's common drift;
  // the drift is tested only when it differs from the held shift by more than a small part of
  // the bound (at rest it does not: one test per body).
  const Vec2 held = shift_, drift = sample_drift(centres);
  const bool two = std::isfinite(drift.x) && std::isfinite(drift.y) &&
                   length_squared(drift - held) > kDriftChange * kDriftChange * bound * bound;
  const int jobs = parts_for(threads, n, 2, 4096);
  if (part_escaped_.size() < static_cast<size_t>(2 * jobs)) part_escaped_.resize(static_cast<size_t>(2 * jobs));
  if (part_count_.size() < static_cast<size_t>(2 * jobs)) part_count_.resize(static_cast<size_t>(2 * jobs));
  run_parts(threads, jobs, [&](int p) {
    // No early exit: a settled pile reads every body anyway. A job keeps patch_limit(n) + 1 of
    // its escaped bodies in each frame at most (enough to tell a patch from a rebuild) and
    // counts them all (to choose the frame). |d| + max(0, R − R⁰) ≤ bound is tested as
    // |d|² ≤ (bound − max(0, R − R⁰))²: no square root; NaN fails it (escapes, rebuilt below).
    std::vector<int>& in_held = part_escaped_[static_cast<size_t>(2 * p)];
    std::vector<int>& in_drift = part_escaped_[static_cast<size_t>(2 * p + 1)];
    in_held.clear();
    in_drift.clear();
    in_held.reserve(limit + 1);  // once: a growing list would allocate step after step while a pile falls
    in_drift.reserve(limit + 1);
    std::size_t count_held = 0, count_drift = 0;
    const Vec2 *x = centres.data(), *x0 = centre0_.data();
    const double *r = reach.data(), *r0 = reach0_.data();
    const int k1 = static_cast<int>(part_begin(n, jobs, p + 1));
    for (int k = static_cast<int>(part_begin(n, jobs, p)); k < k1; ++k) {
      const double room = bound - std::max(0.0, r[k] - r0[k]);
      const double dx = x[k].x - x0[k].x, dy = x[k].y - x0[k].y;
      const double hx = dx - held.x, hy = dy - held.y, fx = dx - drift.x, fy = dy - drift.y;
      const bool out_held = !(room >= 0 && hx * hx + hy * hy <= room * room);
      const bool out_drift = two && !(room >= 0 && fx * fx + fy * fy <= room * room);
      if (!(out_held || out_drift)) continue;  // most bodies at rest: a branch that predicts well
      count_held += out_held ? 1 : 0;
      count_drift += out_drift ? 1 : 0;
      if (out_held && in_held.size() <= limit) in_held.push_back(k);
      if (out_drift && in_drift.size() <= limit) in_drift.push_back(k);
    }
    part_count_[static_cast<size_t>(2 * p)] = count_held;
    part_count_[static_cast<size_t>(2 * p + 1)] = count_drift;
  });
  std::size_t count_held = 0, count_drift = 0;
  for (int p = 0; p < jobs; ++p) {
    count_held += part_count_[static_cast<size_t>(2 * p)];
    count_drift += part_count_[static_cast<size_t>(2 * p + 1)];
  }
  const int frame = two && count_drift < count_held ? 1 : 0;
  reserve_with_headroom(escaped_, static_cast<std::size_t>(jobs) * (limit + 1));
  if (frame == 1) shift_ = drift;
  for (int p = 0; p < jobs; ++p) {
    const std::vector<int>& mine = part_escaped_[static_cast<size_t>(2 * p + frame)];
    escaped_.insert(escaped_.end(), mine.begin(), mine.end());
  }
  // A non-finite body rebuilds, and the broad phase reports it.
  for (const int e : escaped_) {
    const auto i = static_cast<size_t>(e);
    if (!std::isfinite(centres[i].x) || !std::isfinite(centres[i].y) || !std::isfinite(reach[i])) return false;
  }
  return true;
}

int CirclePairCache::cell_of(Vec2 x) const {
  // Clamped to the grid (a body that left the anchors' box at the grid's build sits in a border
  // cell): the clamp is monotone, so a query's clamped range still covers every anchor within
  // its reach. NaN lands in cell 0 (an anchor never is: find_escaped() rebuilds on one).
  double cx = std::floor((x.x - origin_.x) / cell_), cy = std::floor((x.y - origin_.y) / cell_);
  cx = cx >= 0 ? std::min(cx, static_cast<double>(cols_ - 1)) : 0.0;
  cy = cy >= 0 ? std::min(cy, static_cast<double>(rows_ - 1)) : 0.0;
  return static_cast<int>(cy) * cols_ + static_cast<int>(cx);
}

void CirclePairCache::build_grid() {
  // Cells of side 2·(max R⁰ + σ), so that an escaped body's reach spans 2 × 2 cells as a rule;
  // larger when the anchors' box would need more than kCellsPerBody cells per body.
  const std::size_t n = centre0_.size();
  Vec2 lo = centre0_[0], hi = centre0_[0];
  for (const Vec2& c : centre0_) {
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y)};
  }
  reach0_max_ = 0;
  for (const double r : reach0_) reach0_max_ = std::max(reach0_max_, r);
  cell_ = 2 * (reach0_max_ + skin_);
  const double w = hi.x - lo.x, h = hi.y - lo.y, most = kCellsPerBody * static_cast<double>(n) + 16;
  if ((w / cell_ + 1) * (h / cell_ + 1) > most) cell_ = std::max(cell_, (w + h) / std::sqrt(most) * 1.5);
  origin_ = lo;
  if (!std::isfinite(w + h + cell_)) cell_ = std::numeric_limits<double>::infinity();  // one cell
  cols_ = std::isfinite(cell_) ? static_cast<int>(w / cell_) + 1 : 1;
  rows_ = std::isfinite(cell_) ? static_cast<int>(h / cell_) + 1 : 1;
  head_.assign(static_cast<size_t>(cols_) * static_cast<size_t>(rows_), -1);
  next_.resize(n);
  prev_.resize(n);
  cell_of_.resize(n);
  for (std::size_t k = n; k-- > 0;) file(static_cast<int>(k), cell_of(centre0_[k]));
  grid_kept_ = true;
}

void CirclePairCache::file(int k, int cell) {
  const auto i = static_cast<size_t>(k);
  const int first = head_[static_cast<size_t>(cell)];
  cell_of_[i] = cell;
  prev_[i] = -1;
  next_[i] = first;
  if (first >= 0) prev_[static_cast<size_t>(first)] = k;
  head_[static_cast<size_t>(cell)] = k;
}

void CirclePairCache::unfile(int k) {
  const auto i = static_cast<size_t>(k);
  if (prev_[i] >= 0) {
    next_[static_cast<size_t>(prev_[i])] = next_[i];
  } else {
    head_[static_cast<size_t>(cell_of_[i])] = next_[i];
  }
  if (next_[i] >= 0) prev_[static_cast<size_t>(next_[i])] = prev_[i];
}

void CirclePairCache::patch(const std::vector<Vec2>& centres, const std::vector<double>& reach) {
  if (!grid_kept_) build_grid();
  // Re-anchor (and re-file) first, so that a pair of two escaped bodies is tested on both new
  // anchors.
  is_escaped_.resize(centres.size(), 0);
  for (const int e : escaped_) {
    const auto i = static_cast<size_t>(e);
    centre0_[i] = centres[i] - shift_;
    reach0_[i] = reach[i];
    reach0_max_ = std::max(reach0_max_, reach[i]);
    is_escaped_[i] = 1;
    const int cell = cell_of(centre0_[i]);
    if (cell != cell_of_[i]) {
      unfile(e);
      file(e, cell);
    }
  }
  // The escaped bodies' pairs against the anchors of the cells within R⁰_e + max R⁰ + 2σ, by the
  // rebuild's test (a pair of two escaped bodies once: from the lower one).
  added_.clear();
  const Vec2* x0 = centre0_.data();
  const double* r0 = reach0_.data();
  const double two_skin = 2 * skin_;
  for (const int e : escaped_) {
    const auto a = static_cast<size_t>(e);
    const Vec2 xa = x0[a];
    const double ra = r0[a], span = ra + reach0_max_ + two_skin;
    const int c0 = cell_of({xa.x - span, xa.y - span}), c1 = cell_of({xa.x + span, xa.y + span});
    for (int row = c0 / cols_; row <= c1 / cols_; ++row) {
      for (int col = c0 % cols_; col <= c1 % cols_; ++col) {
        for (int j = head_[static_cast<size_t>(row * cols_ + col)]; j >= 0; j = next_[static_cast<size_t>(j)]) {
          const auto b = static_cast<size_t>(j);
          if (j == e || (is_escaped_[b] != 0 && j < e)) continue;
          const double limit = ra + r0[b] + two_skin;
          const double dx = x0[b].x - xa.x, dy = x0[b].y - xa.y;
          if (dx * dx + dy * dy < limit * limit) added_.emplace_back(std::min(e, j), std::max(e, j));
        }
      }
    }
  }
  std::sort(added_.begin(), added_.end());
  merge_patched();
}

void CirclePairCache::merge_patched() {
  // The kept pairs without the escaped bodies, merged with their new pairs in sorted order
  // (written through a pointer into room for both: no capacity check per pair).
  reserve_with_headroom(merged_, pairs_.size() + added_.size());
  merged_.resize(pairs_.size() + added_.size());
  std::pair<int, int>* out = merged_.data();
  const char* gone = is_escaped_.data();
  auto next = added_.begin();
  for (const auto& pr : pairs_) {
    if ((gone[pr.first] | gone[pr.second]) != 0) continue;
    for (; next != added_.end() && *next < pr; ++next) *out++ = *next;
    *out++ = pr;
  }
  out = std::copy(next, added_.end(), out);
  merged_.resize(static_cast<size_t>(out - merged_.data()));
  pairs_.swap(merged_);
  for (const int e : escaped_) is_escaped_[static_cast<size_t>(e)] = 0;
}

void CirclePairCache::rebuild(const std::vector<Vec2>& centres, const std::vector<double>& reach,
                              UniformGridBroadPhase& broad_phase, int threads) {
  const std::size_t n = centres.size();
  double largest = 0;
  for (const double r : reach) largest = std::max(largest, r);
  skin_ = kSkinOfReach * largest;
  kept_ = std::isfinite(skin_) && skin_ > 0;
  if (!kept_) {  // no skin to keep a list with: the broad phase's pairs as they are
    broad_phase.find_pairs(centres, reach, pairs_, threads);
    return;
  }
  grid_kept_ = false;  // built at the first patch (patch())
  shift_ = {};
  centre0_.assign(centres.begin(), centres.end());
  reach0_.assign(reach.begin(), reach.end());
  grown_.resize(n);
  for (std::size_t k = 0; k < n; ++k) grown_[k] = reach[k] + skin_;
  broad_phase.find_pairs(centres, grown_, boxes_, threads);
  pairs_.clear();
  reserve_with_headroom(pairs_, boxes_.size());
  for (const auto& [i, j] : boxes_) {
    const auto a = static_cast<size_t>(i), b = static_cast<size_t>(j);
    const double limit = reach[a] + reach[b] + 2 * skin_;
    if (length_squared(centres[b] - centres[a]) < limit * limit) pairs_.emplace_back(i, j);
  }
}

}  // namespace dc
