// The bench's order statistics (quantiles.hpp): quantile of unsorted values is quantile_sorted
// of the sorted ones, the quartiles are its ¼, ½, ¾ points, and bad input is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "dc/bench/quantiles.hpp"
#include "dc/core/error.hpp"

namespace dc {
namespace {

TEST(Quantiles, QuantileOfUnsortedValuesIsQuantileSortedOfTheSortedOnes) {
  const std::vector<double> v = {7.5, -1.0, 3.25, 10.0, 0.5, 3.25, 2.0};
  std::vector<double> sorted = v;
  std::sort(sorted.begin(), sorted.end());
  for (const double p : {0.0, 0.1, 0.25, 0.5, 0.9, 1.0}) EXPECT_EQ(bench::quantile(v, p), bench::quantile_sorted(sorted, p));
  const bench::Quartiles q = bench::quartiles(v);
  EXPECT_EQ(q.q1, bench::quantile(v, 0.25));
  EXPECT_EQ(q.median, bench::quantile(v, 0.5));
  EXPECT_EQ(q.q3, bench::quantile(v, 0.75));
  EXPECT_EQ(bench::quantile(v, 0.0), -1.0);
  EXPECT_EQ(bench::quantile(v, 1.0), 10.0);
  // Linear interpolation between order statistics at p·(n − 1).
  EXPECT_DOUBLE_EQ(bench::quantile({1.0, 2.0, 3.0, 4.0}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(bench::quantile({4.0, 1.0, 3.0, 2.0}, 1.0 / 6.0), 1.5);
}

TEST(Quantiles, EmptyGivesNaNAndBadInputIsRefused) {
  EXPECT_TRUE(std::isnan(bench::quantile({}, 0.5)));
  EXPECT_TRUE(std::isnan(bench::quartiles({}).median));
  EXPECT_THROW((void)bench::quantile({1.0}, -0.1), InvalidArgument);
  EXPECT_THROW((void)bench::quantile({1.0}, 1.5), InvalidArgument);
  EXPECT_THROW((void)bench::quantile({1.0, std::numeric_limits<double>::quiet_NaN()}, 0.5), InvalidArgument);
}

}  // namespace
}  // namespace dc
