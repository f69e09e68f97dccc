#include "dc/engine/circle_pair_cache.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "world/parts/step_parts.hpp"

namespace dc {
namespace {

/// σ ÷ the largest reach at a rebuild: a larger skin keeps the list longer and hands the
/// narrow phase more pairs that are not in contact.
constexpr double kSkinOfReach = 0.1;
/// The motion a body may make before the list is rebuilt, as a fraction of σ (circle_pair_cache.hpp).
constexpr double kMotionOfSkin = 0.9;
/// A list that served fewer steps after its rebuild than this did not pay for its skin: the
/// broad phase then runs plainly (no list) for a number of steps that doubles up to kMaxPlain.
constexpr int kPayingUses = 2;
constexpr int kMaxPlain = 32;
/// Escaped bodies a step patches at most (circle_pair_cache.hpp): a patch costs one distance
/// test per body and escaped body (a streamed loop) plus a pass over the list, where a rebuild
/// files every grown box in the grid, tests its neighbours and sorts the pairs, many times that
/// per body; beyond this count the pile is on the move and the list is rebuilt.
constexpr std::size_t kMaxPatched = 16;

}  // namespace

const std::vector<std::pair<int, int>>& CirclePairCache::pairs(const std::vector<Vec2>& centres,
                                                              const std::vector<double>& reach,
                                                              UniformGridBroadPhase& broad_phase, int threads) {
  patched_ = false;
  rebuilt_ = !(kept_ && find_escaped(centres, reach, threads) && escaped_.size() <= kMaxPatched);
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

bool CirclePairCache::find_escaped(const std::vector<Vec2>& centres, const std::vector<double>& reach, int threads) {
  escaped_.clear();
  const int n = static_cast<int>(centres.size());
  if (centre0_.size() != centres.size() || reach.size() != centres.size()) return false;
  const double bound = kMotionOfSkin * skin_;
  const int jobs = parts_for(threads, n, 2, 4096);
  if (part_escaped_.size() < static_cast<size_t>(jobs)) part_escaped_.resize(static_cast<size_t>(jobs));
  run_parts(threads, jobs, [&](int p) {
    // No early exit: a settled pile reads every body anyway. A job keeps kMaxPatched + 1 of
    // its escaped bodies at most: enough to tell a patch from a rebuild.
    std::vector<int>& mine = part_escaped_[static_cast<size_t>(p)];
    mine.clear();
    for (int k = static_cast<int>(part_begin(n, jobs, p)); k < part_begin(n, jobs, p + 1); ++k) {
      const auto i = static_cast<size_t>(k);
      const double motion = std::sqrt(length_squared(centres[i] - centre0_[i])) + std::max(0.0, reach[i] - reach0_[i]);
      if (!(motion <= bound) && mine.size() <= kMaxPatched) mine.push_back(k);  // NaN escapes (rebuilt below)
    }
  });
  for (int p = 0; p < jobs; ++p) {
    const std::vector<int>& mine = part_escaped_[static_cast<size_t>(p)];
    escaped_.insert(escaped_.end(), mine.begin(), mine.end());
  }
  // A non-finite body rebuilds, and the broad phase reports it.
  for (const int e : escaped_) {
    const auto i = static_cast<size_t>(e);
    if (!std::isfinite(centres[i].x) || !std::isfinite(centres[i].y) || !std::isfinite(reach[i])) return false;
  }
  return true;
}

void CirclePairCache::patch(const std::vector<Vec2>& centres, const std::vector<double>& reach) {
  // Re-anchor first, so that a pair of two escaped bodies is tested on both new anchors.
  is_escaped_.resize(centres.size(), 0);
  for (const int e : escaped_) {
    const auto i = static_cast<size_t>(e);
    centre0_[i] = centres[i];
    reach0_[i] = reach[i];
    is_escaped_[i] = 1;
  }
  // The escaped bodies' pairs against every anchor, by the rebuild's test (a pair of two escaped
  // bodies once: from the lower one).
  added_.clear();
  const int n = static_cast<int>(centres.size());
  hit_.resize(centres.size());
  const Vec2* x0 = centre0_.data();
  const double* r0 = reach0_.data();
  for (const int e : escaped_) {
    // The test against every anchor as a byte per body (a branch-free loop the compiler
    // vectorises), then the rare hits read eight bytes at a time.
    const auto a = static_cast<size_t>(e);
    const Vec2 xa = x0[a];
    const double ra = r0[a], two_skin = 2 * skin_;
    unsigned char* hit = hit_.data();
    for (int j = 0; j < n; ++j) {
      const double limit = ra + r0[j] + two_skin;
      const double dx = x0[j].x - xa.x, dy = x0[j].y - xa.y;
      hit[j] = static_cast<unsigned char>(dx * dx + dy * dy < limit * limit);
    }
    for (int j0 = 0; j0 < n; j0 += 8) {
      std::uint64_t word = 0;
      std::memcpy(&word, hit + j0, static_cast<size_t>(std::min(8, n - j0)));
      if (word == 0) continue;
      for (int j = j0; j < std::min(n, j0 + 8); ++j) {
        // A pair of two escaped bodies once: from the lower one.
        if (hit[j] == 0 || j == e || (is_escaped_[static_cast<size_t>(j)] != 0 && j < e)) continue;
        added_.emplace_back(std::min(e, j), std::max(e, j));
      }
    }
  }
  std::sort(added_.begin(), added_.end());
  // The kept pairs without the escaped bodies, merged with their new pairs in sorted order
  // (written through a pointer into room for both: no capacity check per pair).
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
  centre0_.assign(centres.begin(), centres.end());
  reach0_.assign(reach.begin(), reach.end());
  grown_.resize(n);
  for (std::size_t k = 0; k < n; ++k) grown_[k] = reach[k] + skin_;
  broad_phase.find_pairs(centres, grown_, boxes_, threads);
  pairs_.clear();
  for (const auto& [i, j] : boxes_) {
    const auto a = static_cast<size_t>(i), b = static_cast<size_t>(j);
    const double limit = reach[a] + reach[b] + 2 * skin_;
    if (length_squared(centres[b] - centres[a]) < limit * limit) pairs_.emplace_back(i, j);
  }
}

}  // namespace dc
