// pgs-colored's serial sweep plan (sweep_plan.hpp): every batch of every colour range once, in
// the ranges' order; ranges of one batch with few lanes on the scalar kernel, consecutive ones
// of one kind merged into one call; wider ranges on the solver's kernel.
#include <gtest/gtest.h>

#include <vector>

#include "solvers/pgs_colored/sweep_plan.hpp"

namespace dc::colored {
namespace {

/// A layout with the given ranges; batch / pair batch b has counts[b] (or pair_counts[b]) lanes.
Prepared with_ranges(std::vector<Range> ranges, const std::vector<int>& counts, const std::vector<int>& pair_counts) {
  Prepared p;
  p.ranges = std::move(ranges);
  p.batches.resize(counts.size());
  for (size_t b = 0; b < counts.size(); ++b) p.batches[b].count = counts[b];
  p.pairs.resize(pair_counts.size());
  for (size_t b = 0; b < pair_counts.size(); ++b) p.pairs[b].count = pair_counts[b];
  return p;
}

bool same(const SweepStep& s, int begin, int end, bool pairs, bool scalar) {
  return s.begin == begin && s.end == end && s.pairs == pairs && s.scalar == scalar;
}

TEST(PgsColoredSweepPlan, ChainOfTinyColoursIsOneScalarCall) {
  // A stack: one manifold per colour, 5 colours of pairs.
  const Prepared p = with_ranges({{0, 1, false, true}, {1, 2, false, true}, {2, 3, false, true}, {3, 4, false, true},
                                  {4, 5, false, true}},
                                 {}, {1, 1, 1, 1, 1});
  std::vector<SweepStep> plan;
  plan_sweep(p, kScalarLanes, plan);
  ASSERT_EQ(plan.size(), 1u);
  EXPECT_TRUE(same(plan[0], 0, 5, true, true));
}

TEST(PgsColoredSweepPlan, KindsAndWidthsKeepTheirOrder) {
  // Colour 0: singles (1 lane) and pairs (2 lanes); colour 1: singles over two batches, pairs of
  // 1 lane; colour 2: pairs of 1 lane (merged with colour 1's); overflow: 3 singles.
  const Prepared p = with_ranges({{0, 1, false, false},
                                  {0, 1, false, true},
                                  {1, 3, false, false},
                                  {1, 2, false, true},
                                  {2, 3, false, true},
                                  {3, 6, true, false}},
                                 {1, 8, 3, 1, 1, 1}, {2, 1, 1});
  std::vector<SweepStep> plan;
  plan_sweep(p, kScalarLanes, plan);
  ASSERT_EQ(plan.size(), 5u);
  EXPECT_TRUE(same(plan[0], 0, 1, false, true));
  EXPECT_TRUE(same(plan[1], 0, 1, true, 2 <= kScalarLanes));
  EXPECT_TRUE(same(plan[2], 1, 3, false, false));  // two batches: the vector kernel
  EXPECT_TRUE(same(plan[3], 1, 3, true, true));
  EXPECT_TRUE(same(plan[4], 3, 6, false, true));  // the overflow set: one lane per batch
}

TEST(PgsColoredSweepPlan, NoScalarLanesKeepsEveryRange) {
  const Prepared p = with_ranges({{0, 1, false, true}, {1, 2, false, true}}, {}, {1, 1});
  std::vector<SweepStep> plan{{7, 8, false, true}};  // cleared first
  plan_sweep(p, 0, plan);
  ASSERT_EQ(plan.size(), 2u);
  EXPECT_TRUE(same(plan[0], 0, 1, true, false));
  EXPECT_TRUE(same(plan[1], 1, 2, true, false));
}

}  // namespace
}  // namespace dc::colored
