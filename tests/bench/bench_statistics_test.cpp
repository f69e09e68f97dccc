// The bench's bootstrap statistics: intervals cover a known median at about the nominal rate,
// identical starters are not distinguishable, clearly different ones are, paired resampling
// really pairs, and a fixed seed gives bit-identical intervals.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "dc/bench/bench_statistics.hpp"
#include "dc/bench/quantiles.hpp"
#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"

namespace dc {
namespace {

using bench::BenchResults;
using bench::BootstrapDef;
using bench::GroupedColumns;
using bench::Interval;
using bench::StarterRecord;

/// G seeds of m values exp(μ_g + ε), μ_g ~ N(0, τ²) (the seed's own level), ε ~ N(0, σ²): the
/// pooled population's median is exp(0) = 1 and its mean exp((τ² + σ²)/2).
GroupedColumns lognormal_groups(Rng& rng, std::size_t G, std::size_t m, double tau, double sigma) {
  GroupedColumns x;
  x.columns.assign(1, {});
  x.offsets.push_back(0);
  for (std::size_t g = 0; g < G; ++g) {
    const double mu = rng.gaussian(tau);
    for (std::size_t k = 0; k < m; ++k) x.columns[0].push_back(std::exp(mu + rng.gaussian(sigma)));
    x.offsets.push_back(x.columns[0].size());
  }
  return x;
}

TEST(BenchStatistics, IntervalsCoverTheTrueMedianAndMeanAtAboutTheNominalRate) {
  // 200 synthetic runs of 20 seeds × 50 steps; 95 % intervals from 500 resamples each. The
  // binomial standard error of the coverage is ~1.5 %, the method's own bias a few per cent.
  Rng data(11), draws(12);
  const double tau = 0.3, sigma = 1.0, true_median = 1.0, true_mean = std::exp(0.5 * (tau * tau + sigma * sigma));
  const int runs = 200;
  int median_hits = 0, mean_hits = 0;
  for (int t = 0; t < runs; ++t) {
    const GroupedColumns x = lognormal_groups(data, 20, 50, tau, sigma);
    const bench::Replicates rep = bench::hierarchical_bootstrap(x, 500, draws);
    median_hits += bench::percentile_interval(bench::median_of(x.columns[0]), rep.median[0], 0.95).contains(true_median);
    mean_hits += bench::percentile_interval(bench::mean_of(x.columns[0]), rep.mean[0], 0.95).contains(true_mean);
  }
  EXPECT_GE(median_hits, 0.88 * runs);
  EXPECT_LE(median_hits, 0.99 * runs);
  EXPECT_GE(mean_hits, 0.85 * runs);
  EXPECT_LE(mean_hits, 0.99 * runs);
}

TEST(BenchStatistics, MedianAndPercentileIntervalBasics) {
  EXPECT_EQ(bench::median_of({3, 1, 2}), 2);
  EXPECT_EQ(bench::median_of({4, 1, 3, 2}), 2.5);
  EXPECT_TRUE(std::isnan(bench::median_of({})));
  EXPECT_EQ(bench::mean_of({1, 2, 6}), 3);
  std::vector<double> rep;
  for (int i = 0; i <= 1000; ++i) rep.push_back(i);
  const Interval iv = bench::percentile_interval(7, rep, 0.95);
  EXPECT_EQ(iv.estimate, 7);
  EXPECT_NEAR(iv.lo, 25, 1e-9);
  EXPECT_NEAR(iv.hi, 975, 1e-9);
  EXPECT_TRUE(std::isnan(bench::percentile_interval(1, {}, 0.95).lo));
  EXPECT_THROW((void)bench::percentile_interval(1, rep, 1.0), InvalidArgument);
}

TEST(BenchStatistics, BootstrapRejectsEmptyGroupsAndRaggedColumns) {
  Rng rng(1);
  GroupedColumns x{{0, 2, 2}, {{1, 2}}};
  EXPECT_THROW((void)bench::hierarchical_bootstrap(x, 10, rng), InvalidArgument);
  x = GroupedColumns{{0, 2}, {{1, 2}, {1}}};
  EXPECT_THROW((void)bench::hierarchical_bootstrap(x, 10, rng), InvalidArgument);
  x = GroupedColumns{{0, 2}, {{1, 2}}};
  EXPECT_THROW((void)bench::hierarchical_bootstrap(x, 0, rng), InvalidArgument);
}

/// A synthetic bench run: per starter (name, value per step as a function of (seed, step)).
BenchResults fake_run(bench::Mode mode, const std::vector<std::pair<std::string, std::function<int(int, int)>>>& s,
                      int seeds = 4, int steps = 60) {
  BenchResults r;
  r.options.mode = mode;
  r.options.sweeps = 1000;
  r.options.seeds.clear();
  for (int g = 1; g <= seeds; ++g) r.options.seeds.push_back(static_cast<std::uint64_t>(g));
  for (const auto& [name, f] : s) {
    StarterRecord rec;
    rec.name = name;
    for (int g = 1; g <= seeds; ++g)
      for (int k = 0; k < steps; ++k) {
        rec.seed.push_back(static_cast<std::uint64_t>(g));
        rec.step.push_back(k);
        rec.sweeps_to_tol.push_back(f(g, k));
        rec.warmstart_ms.push_back(0.01);
        rec.solve_ms.push_back(f(g, k) < 0 ? 1.001 : 1e-3 * f(g, k));
      }
    r.starters.push_back(std::move(rec));
  }
  return r;
}

/// Irregular "sweeps" per (seed, step): a seed level and a spread within the seed.
int sweeps_of(int g, int k) { return 100 + 37 * g + (k * 7919) % 251; }

const bench::RatioStatistics& ratio(const bench::BenchStatistics& s, const std::string& n, const std::string& ref) {
  for (const auto& q : s.ratios)
    if (q.name == n && q.reference == ref) return q;
  throw std::runtime_error("no ratio " + n + "/" + ref);
}

TEST(BenchStatistics, IdenticalStartersAreNotDistinguishableInEitherMode) {
  for (const auto mode : {bench::Mode::Paired, bench::Mode::Rollout}) {
    const auto s = bench::bench_statistics(fake_run(mode, {{"zero", sweeps_of}, {"builtin", sweeps_of}}));
    const auto& q = ratio(s, "builtin", "zero");
    EXPECT_EQ(q.median_sweeps.estimate, 1.0);
    EXPECT_TRUE(q.median_sweeps.contains(1.0));
    EXPECT_TRUE(q.mean_total_ms.contains(1.0));
    EXPECT_FALSE(q.sweeps_distinguishable());
    if (mode == bench::Mode::Paired) {  // the same draws for both: the ratio is 1 in every replicate
      EXPECT_EQ(q.median_sweeps.lo, 1.0);
      EXPECT_EQ(q.median_sweeps.hi, 1.0);
    } else {  // independent draws: an interval of positive width around 1
      EXPECT_LT(q.median_sweeps.lo, 1.0);
      EXPECT_GT(q.median_sweeps.hi, 1.0);
    }
  }
}

TEST(BenchStatistics, ClearlyDifferentStartersAreDistinguishableInEitherMode) {
  const auto quarter = [](int g, int k) { return sweeps_of(g, k) / 4; };
  for (const auto mode : {bench::Mode::Paired, bench::Mode::Rollout}) {
    const auto s = bench::bench_statistics(fake_run(mode, {{"zero", sweeps_of}, {"builtin", quarter}}));
    const auto& q = ratio(s, "builtin", "zero");
    EXPECT_TRUE(q.sweeps_distinguishable());
    EXPECT_TRUE(q.total_distinguishable());
    EXPECT_LT(q.median_sweeps.hi, 1.0);
    EXPECT_GT(ratio(s, "zero", "builtin").median_sweeps.lo, 1.0);
    // The starter's own intervals are separate too.
    EXPECT_FALSE(s.starters[0].sweeps.median.overlaps(s.starters[1].sweeps.median));
  }
}

// Paired resampling evaluates numerator and denominator on the same steps: an exact per-step
// factor of ½ gives a zero-width ratio interval, independent resampling a wide one.
TEST(BenchStatistics, PairedRatiosUseTheSameResampledSteps) {
  const auto twice = [](int g, int k) { return 2 * sweeps_of(g, k); };
  const auto paired = bench::bench_statistics(fake_run(bench::Mode::Paired, {{"zero", twice}, {"builtin", sweeps_of}}));
  const auto& p = ratio(paired, "builtin", "zero");
  EXPECT_EQ(p.median_sweeps.lo, 0.5);
  EXPECT_EQ(p.median_sweeps.hi, 0.5);
  EXPECT_EQ(p.mean_sweeps.lo, 0.5);
  EXPECT_EQ(p.mean_sweeps.hi, 0.5);
  const auto rollout =
      bench::bench_statistics(fake_run(bench::Mode::Rollout, {{"zero", twice}, {"builtin", sweeps_of}}));
  const auto& q = ratio(rollout, "builtin", "zero");
  EXPECT_LT(q.median_sweeps.lo, 0.5);
  EXPECT_GT(q.median_sweeps.hi, 0.5);
}

TEST(BenchStatistics, AFixedSeedGivesIdenticalIntervalsAndTheSeedIsUsed) {
  const auto other = [](int g, int k) { return sweeps_of(g, k) + (k % 5) * g; };
  for (const auto mode : {bench::Mode::Paired, bench::Mode::Rollout}) {
    const BenchResults r = fake_run(mode, {{"zero", sweeps_of}, {"builtin", other}, {"cnn", other}});
    const auto a = bench::bench_statistics(r), b = bench::bench_statistics(r);
    BootstrapDef d;
    d.seed += 1;
    const auto c = bench::bench_statistics(r, d);
    ASSERT_EQ(a.starters.size(), 3u);
    ASSERT_EQ(a.ratios.size(), 4u);  // builtin, cnn / zero; zero, cnn / builtin
    bool differs = false;
    for (std::size_t i = 0; i < a.starters.size(); ++i) {
      for (auto m : {&bench::StarterStatistics::sweeps, &bench::StarterStatistics::total_ms}) {
        EXPECT_EQ((a.starters[i].*m).median.lo, (b.starters[i].*m).median.lo);
        EXPECT_EQ((a.starters[i].*m).median.hi, (b.starters[i].*m).median.hi);
        EXPECT_EQ((a.starters[i].*m).mean.lo, (b.starters[i].*m).mean.lo);
        EXPECT_EQ((a.starters[i].*m).mean.hi, (b.starters[i].*m).mean.hi);
        differs |= (a.starters[i].*m).mean.lo != (c.starters[i].*m).mean.lo;
      }
    }
    for (std::size_t i = 0; i < a.ratios.size(); ++i) {
      EXPECT_EQ(a.ratios[i].median_sweeps.lo, b.ratios[i].median_sweeps.lo);
      EXPECT_EQ(a.ratios[i].mean_total_ms.hi, b.ratios[i].mean_total_ms.hi);
    }
    EXPECT_TRUE(differs) << "another BootstrapDef::seed must give other draws";
  }
}

TEST(BenchStatistics, NeverConvergedCountsAsSweepsPlusOneAndSeedMediansArePerSeed) {
  const auto never_on_seed_2 = [](int g, int k) { return g == 2 ? -1 : 10 * g + k % 3; };
  const auto s = bench::bench_statistics(fake_run(bench::Mode::Paired, {{"zero", never_on_seed_2}}, 3, 30));
  ASSERT_EQ(s.starters.size(), 1u);
  const auto& m = s.starters[0].sweeps.seed_medians;
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0], 11);
  EXPECT_EQ(m[1], 1001);  // sweeps + 1
  EXPECT_EQ(m[2], 31);
  EXPECT_EQ(s.starters[0].steps, 90u);
  EXPECT_EQ(s.starters[0].sweeps.median.estimate, 31);
  EXPECT_LE(s.starters[0].sweeps.median.hi, 1001);
  EXPECT_TRUE(s.ratios.empty());  // no builtin, and zero is not compared with itself
}

TEST(BenchStatistics, PairedModeRequiresIdenticalSteps) {
  BenchResults r = fake_run(bench::Mode::Paired, {{"zero", sweeps_of}, {"builtin", sweeps_of}});
  r.starters[1].step[3] = 999;
  EXPECT_THROW((void)bench::bench_statistics(r), InvalidArgument);
}

}  // namespace
}  // namespace dc
