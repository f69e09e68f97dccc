#include "dc/bench/bench_statistics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"

namespace dc::bench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// FNV-1a of a starter's name: its own random stream in rollout mode, independent of the
/// table order (adding a starter does not change another's interval).
std::uint64_t name_hash(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const unsigned char c : s) h = (h ^ c) * 0x100000001b3ULL;
  return h;
}

/// One starter's per-step figures regrouped by seed (order of BenchOptions::seeds).
struct Grouped {
  GroupedColumns cols;                 ///< columns: 0 = sweeps to tol, 1 = total ms
  std::vector<std::size_t> order;      ///< record index of each grouped row
  std::vector<double> seed_median_sweeps, seed_median_total;
};

Grouped group_by_seed(const BenchResults& r, const StarterRecord& rec) {
  const double never = static_cast<double>(r.options.sweeps) + 1.0;
  Grouped g;
  g.cols.columns.assign(2, {});
  g.cols.offsets.push_back(0);
  for (const std::uint64_t seed : r.options.seeds) {
    std::vector<double> sw, tot;
    for (std::size_t i = 0; i < rec.seed.size(); ++i) {
      if (rec.seed[i] != seed) continue;
      g.order.push_back(i);
      sw.push_back(rec.sweeps_to_tol[i] < 0 ? never : rec.sweeps_to_tol[i]);
      tot.push_back(rec.warmstart_ms[i] + rec.solve_ms[i]);
    }
    g.seed_median_sweeps.push_back(median_of(sw));
    g.seed_median_total.push_back(median_of(tot));
    if (sw.empty()) continue;  // a seed without evaluated steps is no group
    g.cols.columns[0].insert(g.cols.columns[0].end(), sw.begin(), sw.end());
    g.cols.columns[1].insert(g.cols.columns[1].end(), tot.begin(), tot.end());
    g.cols.offsets.push_back(g.cols.columns[0].size());
  }
  return g;
}

/// Replicates of one starter: median/mean of sweeps and total (NaN-filled without data).
struct StarterReplicates {
  std::vector<double> median_sweeps, mean_sweeps, median_total, mean_total;
};

std::vector<double> quotient(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> q(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) q[i] = a[i] / b[i];
  return q;
}

}  // namespace

Interval percentile_interval(double estimate, std::vector<double> rep, double level) {
  if (!(level > 0 && level < 1)) throw InvalidArgument("bootstrap: level must lie in (0, 1)");
  Interval out;
  out.estimate = estimate;
  if (rep.empty() || std::any_of(rep.begin(), rep.end(), [](double x) { return std::isnan(x); })) return out;
  std::sort(rep.begin(), rep.end());
  out.lo = quantile_sorted(rep, 0.5 * (1.0 - level));
  out.hi = quantile_sorted(rep, 0.5 * (1.0 + level));
  return out;
}

Replicates hierarchical_bootstrap(const GroupedColumns& x, int resamples, Rng& rng) {
  if (resamples < 1) throw InvalidArgument("bootstrap: resamples must be >= 1");
  const auto& off = x.offsets;
  if (off.size() < 2 || off.front() != 0) throw InvalidArgument("bootstrap: need at least one group, offsets from 0");
  for (std::size_t g = 1; g < off.size(); ++g)
    if (off[g] <= off[g - 1]) throw InvalidArgument("bootstrap: group " + std::to_string(g - 1) + " is empty");
  for (std::size_t c = 0; c < x.columns.size(); ++c)
    if (x.columns[c].size() != off.back())
      throw InvalidArgument("bootstrap: column " + std::to_string(c) + " has " + std::to_string(x.columns[c].size()) +
                            " rows, the groups " + std::to_string(off.back()));
  const std::size_t G = off.size() - 1, C = x.columns.size(), B = static_cast<std::size_t>(resamples);
  Replicates rep;
  rep.median.assign(C, std::vector<double>(B));
  rep.mean.assign(C, std::vector<double>(B));
  std::vector<std::size_t> idx;
  std::vector<double> buf;
  for (std::size_t b = 0; b < B; ++b) {
    // Stage 1: G seeds with replacement; stage 2: n_g steps with replacement within each.
    idx.clear();
    for (std::size_t k = 0; k < G; ++k) {
      const std::size_t g = rng.uniform_int(G), lo = off[g], n = off[g + 1] - lo;
      for (std::size_t j = 0; j < n; ++j) idx.push_back(lo + rng.uniform_int(n));
    }
    for (std::size_t c = 0; c < C; ++c) {
      buf.resize(idx.size());
      double sum = 0;
      for (std::size_t i = 0; i < idx.size(); ++i) sum += buf[i] = x.columns[c][idx[i]];
      rep.mean[c][b] = sum / static_cast<double>(idx.size());
      rep.median[c][b] = median_of(buf);  // copies buf; nth_element reorders the copy
    }
  }
  return rep;
}

namespace {

/// The bootstrap replicates of every starter (NaN-filled for a starter without evaluated
/// steps, and for all of them in paired mode when the first has none). Paired: one draw per
/// replicate for all starters, from Rng(def.seed); rollout: each starter its own stream,
/// Rng(def.seed ^ hash of its name).
std::vector<StarterReplicates> starter_replicates(const BenchResults& r, const std::vector<Grouped>& grouped,
                                                  const BootstrapDef& def, bool paired) {
  const std::size_t W = r.starters.size(), B = static_cast<std::size_t>(def.resamples);
  const std::vector<double> nans(B, kNaN);
  std::vector<StarterReplicates> reps(W, StarterReplicates{nans, nans, nans, nans});
  if (paired && W > 0 && !grouped[0].order.empty()) {
    // One draw per replicate for all starters: they were evaluated on identical steps.
    GroupedColumns all;
    all.offsets = grouped[0].cols.offsets;
    for (std::size_t i = 0; i < W; ++i) {
      if (r.starters[i].step != r.starters[0].step || r.starters[i].seed != r.starters[0].seed)
        throw InvalidArgument("bench statistics: paired mode, but starter '" + r.starters[i].name +
                              "' was evaluated on other steps than '" + r.starters[0].name + "'");
      for (const auto& c : grouped[i].cols.columns) all.columns.push_back(c);
    }
    Rng rng(def.seed);
    const Replicates rp = hierarchical_bootstrap(all, def.resamples, rng);
    for (std::size_t i = 0; i < W; ++i)
      reps[i] = {rp.median[2 * i], rp.mean[2 * i], rp.median[2 * i + 1], rp.mean[2 * i + 1]};
  } else if (!paired) {
    for (std::size_t i = 0; i < W; ++i) {
      if (grouped[i].order.empty()) continue;
      Rng rng(def.seed ^ name_hash(r.starters[i].name));
      const Replicates rp = hierarchical_bootstrap(grouped[i].cols, def.resamples, rng);
      reps[i] = {rp.median[0], rp.mean[0], rp.median[1], rp.mean[1]};
    }
  }
  return reps;
}

/// A starter's point estimates: median sweeps, mean sweeps, median total, mean total.
using Estimates = std::array<double, 4>;

Estimates estimates(const Grouped& g) {
  const auto& cols = g.cols.columns;
  return {median_of(cols[0]), mean_of(cols[0]), median_of(cols[1]), mean_of(cols[1])};
}

StarterStatistics starter_statistics(const std::string& name, const Grouped& g, const Estimates& est,
                                     const StarterReplicates& rep, double level) {
  StarterStatistics s;
  s.name = name;
  s.steps = g.cols.columns[0].size();
  s.sweeps.median = percentile_interval(est[0], rep.median_sweeps, level);
  s.sweeps.mean = percentile_interval(est[1], rep.mean_sweeps, level);
  s.total_ms.median = percentile_interval(est[2], rep.median_total, level);
  s.total_ms.mean = percentile_interval(est[3], rep.mean_total, level);
  s.sweeps.seed_medians = g.seed_median_sweeps;
  s.total_ms.seed_medians = g.seed_median_total;
  return s;
}

/// Starter `name` against `reference`: the ratio of the estimates, and the interval of the
/// replicate-by-replicate quotients (paired mode: both on the same resampled steps).
RatioStatistics ratio_statistics(const std::string& name, const char* reference, const Estimates& e,
                                 const Estimates& ref, const StarterReplicates& rep,
                                 const StarterReplicates& ref_rep, double level) {
  RatioStatistics q;
  q.name = name;
  q.reference = reference;
  q.median_sweeps = percentile_interval(e[0] / ref[0], quotient(rep.median_sweeps, ref_rep.median_sweeps), level);
  q.mean_sweeps = percentile_interval(e[1] / ref[1], quotient(rep.mean_sweeps, ref_rep.mean_sweeps), level);
  q.median_total_ms = percentile_interval(e[2] / ref[2], quotient(rep.median_total, ref_rep.median_total), level);
  q.mean_total_ms = percentile_interval(e[3] / ref[3], quotient(rep.mean_total, ref_rep.mean_total), level);
  return q;
}

}  // namespace

BenchStatistics bench_statistics(const BenchResults& r, const BootstrapDef& def) {
  if (def.resamples < 1) throw ConfigError("bench statistics: resamples must be >= 1");
  if (!(def.level > 0 && def.level < 1)) throw ConfigError("bench statistics: level must lie in (0, 1)");
  BenchStatistics out;
  out.def = def;
  out.paired = r.options.mode == Mode::Paired;
  out.seeds = r.options.seeds;
  out.sweeps = r.options.sweeps;
  const std::size_t W = r.starters.size();

  std::vector<Grouped> grouped;
  for (const StarterRecord& rec : r.starters) grouped.push_back(group_by_seed(r, rec));
  const std::vector<StarterReplicates> reps = starter_replicates(r, grouped, def, out.paired);

  std::vector<Estimates> est(W);
  for (std::size_t i = 0; i < W; ++i) {
    est[i] = estimates(grouped[i]);
    out.starters.push_back(starter_statistics(r.starters[i].name, grouped[i], est[i], reps[i], def.level));
  }

  // Every starter against zero, then against builtin (when it ran; never itself).
  for (const char* ref : {"zero", "builtin"}) {
    std::size_t j = W;
    for (std::size_t i = 0; i < W; ++i)
      if (r.starters[i].name == ref) j = i;
    if (j == W) continue;
    for (std::size_t i = 0; i < W; ++i)
      if (i != j)
        out.ratios.push_back(ratio_statistics(r.starters[i].name, ref, est[i], est[j], reps[i], reps[j], def.level));
  }
  return out;
}

}  // namespace dc::bench
