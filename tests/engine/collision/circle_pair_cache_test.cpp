// CirclePairCache: the pairs kept across steps hold every pair a fresh broad phase would give
// whose circles are within reach, in the same sorted order, while the bodies move by small steps
// (the kept list serves) and by large ones (it is rebuilt), on one thread and on several.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "dc/engine/broad_phase.hpp"
#include "dc/engine/circle_pair_cache.hpp"

namespace dc {
namespace {

using Pairs = std::vector<std::pair<int, int>>;

/// The pairs of `candidates` whose centres are within reach[i] + reach[j] (the narrow phase's
/// acceptance, on the circles' own reaches).
Pairs within_reach(const Pairs& candidates, const std::vector<Vec2>& x, const std::vector<double>& reach) {
  Pairs out;
  for (const auto& [i, j] : candidates) {
    const auto a = static_cast<size_t>(i), b = static_cast<size_t>(j);
    const double limit = reach[a] + reach[b];
    if (length_squared(x[b] - x[a]) < limit * limit) out.emplace_back(i, j);
  }
  return out;
}

TEST(CirclePairCache, KeptPairsHoldEveryPairInReachInOrder) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(0.0, 60.0), rad(0.2, 0.6), unit(-1.0, 1.0);
  const int n = 3000;
  std::vector<Vec2> x(n);
  std::vector<double> reach(n);
  for (int k = 0; k < n; ++k) {
    x[static_cast<size_t>(k)] = {pos(rng), pos(rng)};
    reach[static_cast<size_t>(k)] = rad(rng);
  }
  for (const int threads : {1, 3}) {
    CirclePairCache cache;
    UniformGridBroadPhase kept_bp, fresh_bp;
    int kept = 0, rebuilt = 0;
    std::vector<Vec2> y = x, v(n);
    for (auto& vk : v) vk = {0.008 * unit(rng), 0.008 * unit(rng)};  // bodies drift towards each other
    std::vector<double> r = reach;
    for (int step = 0; step < 60; ++step) {
      // Drifts of a few hundredths of the skin per step (the list serves a few steps, then
      // expires); every 10th step one body jumps (a rebuild).
      const double jump = step % 10 == 9 ? 5.0 : 0.0;
      for (int k = 0; k < n; ++k) {
        auto& c = y[static_cast<size_t>(k)];
        c = {c.x + v[static_cast<size_t>(k)].x + (k == step ? jump : 0.0), c.y + v[static_cast<size_t>(k)].y};
        r[static_cast<size_t>(k)] = reach[static_cast<size_t>(k)] * (1 + 0.002 * unit(rng));
      }
      const Pairs& from_cache = cache.pairs(y, r, kept_bp, threads);
      (cache.rebuilt() ? rebuilt : kept) += 1;
      ASSERT_TRUE(std::is_sorted(from_cache.begin(), from_cache.end())) << "step " << step;
      Pairs fresh;
      fresh_bp.find_pairs(y, r, fresh, threads);
      ASSERT_EQ(within_reach(fresh, y, r), within_reach(from_cache, y, r)) << "step " << step << ", " << threads
                                                                          << " threads";
    }
    EXPECT_GT(kept, 20) << threads << " threads";
    EXPECT_GE(rebuilt, 8) << threads << " threads";
  }
}

TEST(CirclePairCache, ABodyCountChangeRebuilds) {
  std::vector<Vec2> x = {{0, 0}, {0.5, 0}, {3, 3}};
  std::vector<double> reach = {0.3, 0.3, 0.3};
  CirclePairCache cache;
  UniformGridBroadPhase bp;
  EXPECT_EQ(cache.pairs(x, reach, bp, 1), (Pairs{{0, 1}}));
  x.push_back({3.4, 3});
  reach.push_back(0.3);
  const Pairs& pairs = cache.pairs(x, reach, bp, 1);
  EXPECT_TRUE(cache.rebuilt());
  EXPECT_EQ(within_reach(pairs, x, reach), (Pairs{{0, 1}, {2, 3}}));
}

}  // namespace
}  // namespace dc
