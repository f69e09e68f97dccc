#include "dc/engine/circle_pair_cache.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace

const std::vector<std::pair<int, int>>& CirclePairCache::pairs(const std::vector<Vec2>& centres,
                                                              const std::vector<double>& reach,
                                                              UniformGridBroadPhase& broad_phase, int threads) {
  rebuilt_ = !(kept_ && still_valid(centres, reach, threads));
  if (!rebuilt_) {
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

bool CirclePairCache::still_valid(const std::vector<Vec2>& centres, const std::vector<double>& reach, int threads) {
  const int n = static_cast<int>(centres.size());
  if (centre0_.size() != centres.size() || reach.size() != centres.size()) return false;
  const double bound = kMotionOfSkin * skin_;
  const int jobs = parts_for(threads, n, 2, 4096);
  part_moved_.assign(static_cast<size_t>(jobs), 0);
  run_parts(threads, jobs, [&](int p) {
    bool moved = false;  // no early exit: a settled pile reads every body anyway
    for (auto k = static_cast<size_t>(part_begin(n, jobs, p)); k < static_cast<size_t>(part_begin(n, jobs, p + 1)); ++k) {
      const double motion = std::sqrt(length_squared(centres[k] - centre0_[k])) + std::max(0.0, reach[k] - reach0_[k]);
      moved |= !(motion <= bound);  // NaN rebuilds, and the broad phase reports it
    }
    part_moved_[static_cast<size_t>(p)] = static_cast<char>(moved);
  });
  return std::none_of(part_moved_.begin(), part_moved_.end(), [](char m) { return m != 0; });
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
