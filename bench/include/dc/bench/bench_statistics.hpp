#pragma once
// Bench statistics that carry their uncertainty (seeds, not steps, set it): bootstrap
// percentile intervals of the median and mean sweeps to tolerance and total time per step,
// per starter, and of their ratios to `zero` and `builtin` (method and caveats: docs/bench.md
// "Uncertainty"). Hierarchical bootstrap: a replicate draws the G seeds with replacement,
// then n_g steps of every drawn seed with replacement; the interval is [q_{α/2}, q_{1−α/2}] of
// B replicates. Paired mode: one draw of (seed, step) indices per replicate serves every
// starter, so a ratio's numerator and denominator see the same steps; rollout mode: each
// starter is resampled independently (its own stream). Deterministic: the draws come from
// dc::Rng seeded from BootstrapDef::seed (and, in rollout mode, the starter's name), so a
// report is reproducible bit for bit. Estimates: median_of / mean_of; bounds: quantile_sorted.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "dc/bench/bench_results.hpp"
#include "dc/bench/quantiles.hpp"  // the order statistics the intervals are made of

namespace dc {
class Rng;
}

namespace dc::bench {

struct BootstrapDef {
  int resamples = 2000;            ///< B replicates (2000: the Monte-Carlo error of a 2.5 % quantile ≈ 0.35 %)
  double level = 0.95;             ///< coverage of the two-sided percentile interval
  std::uint64_t seed = 0x16b0075ULL;  ///< dc::Rng seed of the draws (fixed: reproducible reports)
};

/// A point estimate with its bootstrap interval. NaN everywhere when there is no data.
struct Interval {
  double estimate = std::numeric_limits<double>::quiet_NaN();
  double lo = std::numeric_limits<double>::quiet_NaN();
  double hi = std::numeric_limits<double>::quiet_NaN();
  [[nodiscard]] bool contains(double x) const { return lo <= x && x <= hi; }
  /// Two intervals overlap (share at least one point).
  [[nodiscard]] bool overlaps(const Interval& o) const { return lo <= o.hi && o.lo <= hi; }
};

/// Per-step values of several columns that share one grouping by seed: group g is rows
/// offsets[g] … offsets[g+1]−1 of every column (offsets has G+1 entries, groups non-empty).
struct GroupedColumns {
  std::vector<std::size_t> offsets;
  std::vector<std::vector<double>> columns;
};

/// The statistic of every column in every replicate: median[c][b], mean[c][b].
struct Replicates {
  std::vector<std::vector<double>> median, mean;
};

/// B hierarchical replicates of the median and mean of each column (all columns see the same
/// draw in a replicate). Throws InvalidArgument on ragged columns or empty groups.
Replicates hierarchical_bootstrap(const GroupedColumns& x, int resamples, Rng& rng);

/// Percentile interval of `replicates` at `level` (quantile_sorted of the sorted replicates
/// at (1 ∓ level)/2) around `estimate`.
Interval percentile_interval(double estimate, std::vector<double> replicates, double level);

/// Median and mean of one per-step figure with their intervals, and the median of each seed.
struct MetricStatistics {
  Interval median, mean;
  std::vector<double> seed_medians;  ///< per seed of BenchOptions::seeds (NaN: no evaluated step)
};

struct StarterStatistics {
  std::string name;
  std::size_t steps = 0;      ///< evaluated steps
  MetricStatistics sweeps;    ///< sweeps to tol; never-converged steps count as sweeps + 1
  MetricStatistics total_ms;  ///< warm start + tolerance-mode solve [ms]; the oracle never counts
};

/// `name` / `reference` of the median and the mean of both figures.
struct RatioStatistics {
  std::string name, reference;
  Interval median_sweeps, mean_sweeps, median_total_ms, mean_total_ms;
  /// The median-sweeps ratio's interval excludes 1 (the starters are distinguishable).
  [[nodiscard]] bool sweeps_distinguishable() const { return !median_sweeps.contains(1.0); }
  [[nodiscard]] bool total_distinguishable() const { return !median_total_ms.contains(1.0); }
};

struct BenchStatistics {
  BootstrapDef def;
  bool paired = true;                 ///< paired bootstrap (paired mode) or independent (rollout)
  int sweeps = 0;                     ///< the run's sweeps: a never-converged step counts as sweeps + 1
  std::vector<std::uint64_t> seeds;   ///< the run's seeds, order of seed_medians
  std::vector<StarterStatistics> starters;  ///< table order
  /// Every starter against `zero`, then against `builtin` (when those ran; never itself).
  std::vector<RatioStatistics> ratios;
};

/// The statistics of a bench run (starters without evaluated steps get NaN intervals).
BenchStatistics bench_statistics(const BenchResults& r, const BootstrapDef& def = {});

}  // namespace dc::bench
