// CirclePairCache: the pairs kept across steps hold every pair a fresh broad phase would give
// whose circles are within reach, in the same sorted order, while the bodies move by small steps
// (the kept list serves) and by large ones (it is rebuilt), on one thread and on several; a few
// bodies moving far are patched into the kept list (re-anchored) with the same guarantee; a
// pile that falls as one keeps its list (the anchors' frame follows its drift), and through its
// fall, landing and settling every pair within reach is in the list.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "dc/engine/broad_phase.hpp"
#include "dc/engine/circle_pair_cache.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "engine/fixed_sweeps.hpp"

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

/// n circles at uniform positions in [0, side]² with uniform reaches in [r_lo, r_hi], drawn from
/// `rng` (positions and reach body by body: the caller's later draws continue the sequence).
struct Scatter {
  std::vector<Vec2> x;
  std::vector<double> reach;
};
Scatter scatter(std::mt19937& rng, int n, double side, double r_lo, double r_hi) {
  std::uniform_real_distribution<double> pos(0.0, side), rad(r_lo, r_hi);
  Scatter out{std::vector<Vec2>(static_cast<size_t>(n)), std::vector<double>(static_cast<size_t>(n))};
  for (size_t k = 0; k < static_cast<size_t>(n); ++k) {
    out.x[k] = {pos(rng), pos(rng)};
    out.reach[k] = rad(rng);
  }
  return out;
}

TEST(CirclePairCache, KeptPairsHoldEveryPairInReachInOrder) {
  std::mt19937 rng(11);
  const int n = 3000;
  const auto [x, reach] = scatter(rng, n, 60.0, 0.2, 0.6);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const int threads : {1, 3}) {
    CirclePairCache cache;
    UniformGridBroadPhase kept_bp, fresh_bp;
    int kept = 0, rebuilt = 0, patched = 0;
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
      patched += cache.patched() ? 1 : 0;
      ASSERT_TRUE(std::is_sorted(from_cache.begin(), from_cache.end())) << "step " << step;
      Pairs fresh;
      fresh_bp.find_pairs(y, r, fresh, threads);
      ASSERT_EQ(within_reach(fresh, y, r), within_reach(from_cache, y, r)) << "step " << step << ", " << threads
                                                                          << " threads";
    }
    EXPECT_GT(kept, 20) << threads << " threads";
    EXPECT_GE(rebuilt + patched, 8) << threads << " threads";
  }
}

TEST(CirclePairCache, AFewEscapedBodiesArePatchedIntoTheKeptList) {
  // A still scene in which a few bodies travel far each step (one of them crossing the scene,
  // two of them side by side, so that a pair of two escaped bodies is found), some still ones
  // sit on their path: every step is a patch, and the pairs within reach are a fresh broad
  // phase's, in order, on one thread and on several.
  std::mt19937 rng(5);
  const int n = 2500;
  const auto [x, reach] = scatter(rng, n, 50.0, 0.3, 0.6);
  const std::vector<int> movers = {17, 18, 1200, 2499};
  for (const int threads : {1, 3}) {
    CirclePairCache cache;
    UniformGridBroadPhase kept_bp, fresh_bp;
    std::vector<Vec2> y = x;
    std::vector<double> r = reach;
    y[17] = {10.0, 10.0};  // 17 and 18 travel together, within reach of each other
    y[18] = {10.5, 10.0};
    (void)cache.pairs(y, r, kept_bp, threads);
    int patched = 0;
    for (int step = 0; step < 40; ++step) {
      for (const int m : movers) {
        auto& c = y[static_cast<size_t>(m)];
        c = {std::fmod(c.x + 1.3, 50.0), std::fmod(c.y + 0.7, 50.0)};
      }
      r[2499] = reach[2499] * (1 + 0.05 * (step % 3));  // a reach that grows and shrinks
      const Pairs& from_cache = cache.pairs(y, r, kept_bp, threads);
      patched += cache.patched() ? 1 : 0;
      EXPECT_FALSE(cache.rebuilt()) << "step " << step;
      ASSERT_TRUE(std::is_sorted(from_cache.begin(), from_cache.end())) << "step " << step;
      ASSERT_TRUE(std::adjacent_find(from_cache.begin(), from_cache.end()) == from_cache.end()) << "step " << step;
      Pairs fresh;
      fresh_bp.find_pairs(y, r, fresh, threads);
      const Pairs want = within_reach(fresh, y, r);
      ASSERT_EQ(want, within_reach(from_cache, y, r)) << "step " << step << ", " << threads << " threads";
      EXPECT_TRUE(std::find(want.begin(), want.end(), std::pair<int, int>{17, 18}) != want.end());
    }
    EXPECT_EQ(patched, 40) << threads << " threads";
  }
}

TEST(CirclePairCache, HundredsOfEscapedBodiesArePatchedThroughTheGrid) {
  // A still scene in which a few hundred bodies jump each step (leaving their grid cells for
  // others, some out of the anchors' box and back, some next to each other): every step is a
  // patch, and since the still bodies sit on their anchors and the reaches do not change, the
  // kept list is the very list a fresh cache builds from a broad phase on the same positions,
  // on one thread and on several.
  std::mt19937 rng(23);
  const int n = 5000;
  const auto [x, reach] = scatter(rng, n, 63.0, 0.3, 0.6);
  std::uniform_real_distribution<double> pos(0.0, 63.0), unit(-1.0, 1.0);
  for (const int threads : {1, 3}) {
    CirclePairCache cache;
    UniformGridBroadPhase kept_bp, fresh_bp;
    std::vector<Vec2> y = x;
    (void)cache.pairs(y, reach, kept_bp, threads);
    int patched = 0;
    for (int step = 0; step < 30; ++step) {
      for (int m = step % 17; m < n; m += 17) {  // 294 or 295 bodies a step, and up to 98 neighbours
        auto& c = y[static_cast<size_t>(m)];
        if (m % 85 == 0) {
          c = {-3.0 - 0.1 * step, 20.0 + 0.5 * unit(rng)};  // out of the grid's box (clamped)
        } else if (m % 51 == 1 && m + 1 < n) {
          c = {pos(rng), pos(rng)};
          y[static_cast<size_t>(m + 1)] = {c.x + 0.4, c.y};  // two escaped bodies within reach
        } else {
          c = {std::fmod(c.x + 3.0 + unit(rng), 63.0), std::fmod(c.y + 2.0 + unit(rng), 63.0)};
        }
      }
      const Pairs& from_cache = cache.pairs(y, reach, kept_bp, threads);
      patched += cache.patched() ? 1 : 0;
      EXPECT_FALSE(cache.rebuilt()) << "step " << step;
      CirclePairCache fresh;
      ASSERT_EQ(fresh.pairs(y, reach, fresh_bp, threads), from_cache) << "step " << step << ", " << threads
                                                                         << " threads";
    }
    EXPECT_EQ(patched, 30) << threads << " threads";
  }
}

/// Every pair (i < j) of circles within reach[i] + reach[j] of each other, by testing all pairs.
Pairs all_pairs_within_reach(const std::vector<Vec2>& x, const std::vector<double>& reach) {
  Pairs out;
  for (size_t i = 0; i < x.size(); ++i)
    for (size_t j = i + 1; j < x.size(); ++j) {
      const double limit = reach[i] + reach[j];  // within_reach()'s test
      if (length_squared(x[j] - x[i]) < limit * limit) out.emplace_back(static_cast<int>(i), static_cast<int>(j));
    }
  return out;
}

TEST(CirclePairCache, AFallingLandingAndSettlingPileKeepsEveryPairInReach) {
  // The scaled seed pile falls from rest as one (its lowest bodies land after some 70 steps),
  // lands and settles. A cache fed the world's centres and narrow-phase reaches each step must
  // hold every pair within reach (all pairs tested), sorted, once each; while the pile falls
  // freely its anchors' frame follows the common drift, so the list of the first step serves
  // (a frame held still would rebuild every few steps: the fall outruns the skin).
  World world(stress::scaled_seed_pile(600));
  const auto solver = make_solver("pgs");
  CirclePairCache cache;
  UniformGridBroadPhase bp;
  std::vector<double> reach;
  int rebuilt = 0, patched = 0, rebuilt_falling = 0;
  constexpr int kFalling = 50, kSteps = 500;
  for (int step = 0; step < kSteps; ++step) {
    const BodyState& b = world.bodies();
    reach.resize(b.size());
    for (int k = 0; k < static_cast<int>(b.size()); ++k)
      reach[static_cast<size_t>(k)] = b.radius[static_cast<size_t>(k)] +
                                      speculative_reach(b, k, world.def().contact, world.def().time.dt);
    const Pairs& from_cache = cache.pairs(b.position, reach, bp, 1);
    rebuilt += cache.rebuilt() ? 1 : 0;
    rebuilt_falling += cache.rebuilt() && step < kFalling ? 1 : 0;
    patched += cache.patched() ? 1 : 0;
    ASSERT_TRUE(std::is_sorted(from_cache.begin(), from_cache.end())) << "step " << step;
    ASSERT_TRUE(std::adjacent_find(from_cache.begin(), from_cache.end()) == from_cache.end()) << "step " << step;
    ASSERT_EQ(within_reach(from_cache, b.position, reach), all_pairs_within_reach(b.position, reach)) << "step " << step;
    world.step(*solver, test::fixed_sweeps(10), World::WarmStart::PreviousLambda);
  }
  EXPECT_EQ(rebuilt_falling, 1);  // the first step's
  EXPECT_GT(patched, 0);
  EXPECT_LT(rebuilt, kSteps / 2);
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
