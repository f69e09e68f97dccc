// The broad phase's kept candidates (broad_phase.hpp): while bodies move by small steps (the
// filter alone), some escape their fat boxes (queries), many escape or the body count changes
// (rebuilds), the pairs equal a fresh grid search's (margin 0) in the same order, on one thread
// and on several, for the circle and the box entry points.
#include <gtest/gtest.h>

#include <random>
#include <utility>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/engine/broad_phase.hpp"

namespace dc {
namespace {

using Pairs = std::vector<std::pair<int, int>>;

struct PathCounts {
  int filtered = 0, queried = 0, rebuilt = 0;
  void add(const UniformGridBroadPhase& bp) {
    (bp.last_rebuilt() ? rebuilt : bp.last_escaped() == 0 ? filtered : queried) += 1;
  }
};

TEST(BroadPhaseKept, CirclePairsEqualAFreshSearch) {
  for (const int threads : {1, 2, 3}) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> pos(0.0, 50.0), rad(0.2, 0.5), unit(-1.0, 1.0);
    std::vector<Vec2> x;
    std::vector<double> r;
    for (int k = 0; k < 4000; ++k) x.push_back({pos(rng), pos(rng)}), r.push_back(rad(rng));
    UniformGridBroadPhase kept, fresh(BroadPhaseDef{.margin = 0});
    PathCounts counts;
    for (int step = 0; step < 80; ++step) {
      const auto n = x.size();
      // Most steps all bodies creep (the filter alone); every 4th a few hundred move further
      // (queries, some of them out of the grid's old bounds); every 10th most of them jump (a
      // rebuild); every 15th bodies come and go (a rebuild).
      for (std::size_t k = 0; k < n; ++k) {
        const double hop = step % 10 == 9 ? 0.5 : (step % 4 == 3 && k % 13 == 0) ? 0.3 : 0.002;
        x[k] = {x[k].x + hop * unit(rng), x[k].y + hop * unit(rng)};
        if (step % 4 == 3 && k == 7) x[k] = {x[k].x + 70.0, x[k].y - 5.0};  // far out of the grid
        if (step % 4 == 1 && k == 7) x[k] = {pos(rng), pos(rng)};
      }
      if (step % 15 == 14) {
        x.resize(n - 300), r.resize(n - 300);
        for (int k = 0; k < 500; ++k) x.push_back({pos(rng), pos(rng)}), r.push_back(rad(rng));
      }
      Pairs got, want;
      kept.find_pairs(x, r, got, threads);
      counts.add(kept);
      fresh.find_pairs(x, r, want, threads);
      ASSERT_EQ(want, got) << "step " << step << ", " << threads << " threads";
      EXPECT_TRUE(fresh.last_rebuilt());
    }
    EXPECT_GT(counts.filtered, 20) << threads << " threads";
    EXPECT_GT(counts.queried, 10) << threads << " threads";
    EXPECT_GT(counts.rebuilt, 8) << threads << " threads";
  }
}

TEST(BroadPhaseKept, BoxPairsEqualAFreshSearch) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> pos(0.0, 30.0), side(0.05, 1.2), unit(-1.0, 1.0);
  const int n = 1500;
  std::vector<Vec2> lo(n), hi(n);
  for (int k = 0; k < n; ++k) {
    lo[static_cast<size_t>(k)] = {pos(rng), pos(rng)};
    hi[static_cast<size_t>(k)] = lo[static_cast<size_t>(k)] + Vec2{side(rng), side(rng)};
  }
  UniformGridBroadPhase kept, fresh(BroadPhaseDef{.margin = 0});
  PathCounts counts;
  for (int step = 0; step < 60; ++step) {
    for (int k = 0; k < n; ++k) {
      const double hop = step % 5 == 4 && k % 7 == 0 ? 0.4 : 0.003;
      const Vec2 d{hop * unit(rng), hop * unit(rng)};
      lo[static_cast<size_t>(k)] = lo[static_cast<size_t>(k)] + d;
      hi[static_cast<size_t>(k)] = hi[static_cast<size_t>(k)] + d + Vec2{0.001 * unit(rng), 0.0};  // boxes deform
    }
    Pairs got, want;
    kept.find_box_pairs(lo, hi, got);
    counts.add(kept);
    fresh.find_box_pairs(lo, hi, want);
    ASSERT_EQ(want, got) << "step " << step;
  }
  EXPECT_GT(counts.filtered, 10);
  EXPECT_GT(counts.queried, 5);
}

TEST(BroadPhaseKept, ThreadCountsGiveTheSamePairsAndTests) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(0.0, 80.0), unit(-1.0, 1.0);
  std::vector<Vec2> x(20000);
  for (auto& c : x) c = {pos(rng), pos(rng)};
  const std::vector<double> r(x.size(), 0.3);
  UniformGridBroadPhase one, two;
  for (int step = 0; step < 12; ++step) {
    for (std::size_t k = 0; k < x.size(); ++k) {
      const double hop = k % 50 == static_cast<std::size_t>(step) ? 0.2 : 0.001;
      x[k] = {x[k].x + hop * unit(rng), x[k].y + hop * unit(rng)};
    }
    Pairs p1, p2;
    one.find_pairs(x, r, p1, 1);
    two.find_pairs(x, r, p2, 2);
    ASSERT_EQ(p1, p2) << "step " << step;
    EXPECT_EQ(one.last_pair_tests(), two.last_pair_tests()) << "step " << step;
    EXPECT_EQ(one.last_rebuilt(), two.last_rebuilt()) << "step " << step;
    EXPECT_EQ(one.last_escaped(), two.last_escaped()) << "step " << step;
  }
}

TEST(BroadPhaseKept, CopiesKeepTheirCandidates) {
  // A World copy copies its broad phase: both go on with their own kept candidates.
  std::vector<Vec2> x = {{0, 0}, {0.5, 0}, {3, 3}, {3.4, 3}};
  const std::vector<double> r(4, 0.3);
  UniformGridBroadPhase a;
  Pairs pa, pb;
  a.find_pairs(x, r, pa);
  UniformGridBroadPhase b = a;
  x[1] = {2.9, 3.2};
  a.find_pairs(x, r, pa);
  b.find_pairs(x, r, pb);
  EXPECT_EQ(pa, (Pairs{{1, 2}, {1, 3}, {2, 3}}));
  EXPECT_EQ(pa, pb);
}

TEST(BroadPhaseKept, RejectsBadOptions) {
  EXPECT_THROW(UniformGridBroadPhase(BroadPhaseDef{.margin = -1}), InvalidArgument);
  EXPECT_THROW(UniformGridBroadPhase(BroadPhaseDef{.margin = 0.1, .max_escaped = 2}), InvalidArgument);
}

}  // namespace
}  // namespace dc
