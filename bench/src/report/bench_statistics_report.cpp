#include "bench_statistics_report.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "dc/bench/json_writer.hpp"
#include "report_format.hpp"

namespace dc::bench {
namespace {

/// A sweep count; above the run's sweeps it means "never converged".
std::string sweeps_cell(double v, int sweeps) { return v > sweeps ? "never" : fmt("%.1f", v); }

std::string interval_cell(const Interval& x, const char* f, int sweeps = -1) {
  auto one = [&](double v) { return sweeps > 0 ? sweeps_cell(v, sweeps) : fmt(f, v); };
  return one(x.estimate) + " [" + one(x.lo) + ", " + one(x.hi) + "]";
}

std::string seed_list(const std::vector<double>& v, const char* f, int sweeps = -1) {
  std::string out;
  for (const double x : v) out += (out.empty() ? "" : " · ") + (sweeps > 0 ? sweeps_cell(x, sweeps) : fmt(f, x));
  return out;
}

void interval_json(JsonWriter& j, const Interval& x) {
  j.begin_object().key("estimate").value(x.estimate).key("lo").value(x.lo).key("hi").value(x.hi).end_object();
}

std::string verdict(bool distinguishable) { return distinguishable ? "distinguishable" : "**not distinguishable**"; }

}  // namespace

std::string indistinguishable_summary(const BenchStatistics& s) {
  std::ostringstream os;
  for (const char* ref : {"zero", "builtin"}) {
    std::string names;
    for (const auto& q : s.ratios)
      if (q.reference == ref && !q.sweeps_distinguishable() && std::isfinite(q.median_sweeps.lo))
        names += (names.empty() ? "" : ", ") + q.name;
    if (!names.empty())
      os << "Not distinguishable from " << ref << " in median sweeps (ratio interval contains 1): " << names
         << ".\n";
  }
  return os.str();
}

std::string statistics_markdown(const BenchStatistics& s) {
  const int sweeps = s.sweeps;
  std::ostringstream md;
  md << "## Uncertainty\n\n";
  md << "Bootstrap " << fmt("%.0f", 100 * s.def.level) << " % intervals (percentile method, "
     << s.def.resamples << " resamples, dc::Rng seed " << s.def.seed
     << "): each resample draws the scene seeds with replacement, then, within every drawn seed, its steps with "
        "replacement (hierarchical bootstrap). "
     << (s.paired ? "Paired mode: the same resampled steps enter every starter, so a ratio's numerator and "
                    "denominator are evaluated on identical steps (paired bootstrap). "
                  : "Rollout mode: steps are not paired across starters (each drives its own trajectory), so "
                    "every starter is resampled independently and a ratio divides independent replicates. ")
     << "Never-converged steps count as " << sweeps + 1 << " sweeps (`never` below); total = warm start + solve "
     << "per step (the oracle never counts). With few seeds (≲ 5) the intervals are too narrow (docs/bench.md "
        "\"Uncertainty\").\n\n";
  md << "| starter | steps | median sweeps [95 % CI] | mean sweeps [95 % CI] | per-seed median sweeps | "
        "median total ms [95 % CI] | mean total ms [95 % CI] | per-seed median total ms |\n";
  md << "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& x : s.starters)
    md << "| " << x.name << " | " << x.steps << " | " << interval_cell(x.sweeps.median, "%.1f", sweeps) << " | "
       << interval_cell(x.sweeps.mean, "%.1f", sweeps) << " | " << seed_list(x.sweeps.seed_medians, "%.1f", sweeps)
       << " | " << interval_cell(x.total_ms.median, "%.3f") << " | " << interval_cell(x.total_ms.mean, "%.3f")
       << " | " << seed_list(x.total_ms.seed_medians, "%.3f") << " |\n";
  md << "\nPer-seed medians are in the order of the seeds";
  for (const auto seed : s.seeds) md << ' ' << seed;
  md << ".\n\n";
  if (!s.ratios.empty()) {
    md << "Ratios (starter / reference) with " << fmt("%.0f", 100 * s.def.level)
       << " % intervals; *not distinguishable* = the interval contains 1.\n\n";
    md << "| starter | / | median sweeps | mean sweeps | median total ms | mean total ms | sweeps | total |\n";
    md << "|---|---|---:|---:|---:|---:|---|---|\n";
    for (const auto& q : s.ratios)
      md << "| " << q.name << " | " << q.reference << " | " << interval_cell(q.median_sweeps, "%.3f") << " | "
         << interval_cell(q.mean_sweeps, "%.3f") << " | " << interval_cell(q.median_total_ms, "%.3f") << " | "
         << interval_cell(q.mean_total_ms, "%.3f") << " | " << verdict(q.sweeps_distinguishable()) << " | "
         << verdict(q.total_distinguishable()) << " |\n";
    md << "\n";
  }
  const std::string same = indistinguishable_summary(s);
  md << (same.empty() ? std::string("Every starter is distinguishable from zero and builtin in median sweeps.\n")
                      : same)
     << "\n";
  return md.str();
}

void statistics_json(JsonWriter& j, const BenchStatistics& s) {
  j.begin_object(JsonWriter::Layout::Lines);
  j.key("method").value("hierarchical percentile bootstrap: seeds with replacement, then steps within each drawn seed");
  j.key("resamples").value(s.def.resamples);
  j.key("level").value(s.def.level);
  j.key("rng_seed").value(s.def.seed);
  j.key("paired").value(s.paired);
  j.key("never_counts_as").value(s.sweeps + 1);
  j.key("seeds").begin_array();
  for (const auto seed : s.seeds) j.value(seed);
  j.end_array();
  j.key("warmstarters").begin_object(JsonWriter::Layout::Lines);
  for (const auto& x : s.starters) {
    j.key(x.name).begin_object();
    j.key("steps").value(x.steps);
    j.key("median_sweeps_to_tol"); interval_json(j, x.sweeps.median);
    j.key("mean_sweeps_to_tol"); interval_json(j, x.sweeps.mean);
    j.key("seed_median_sweeps_to_tol").array(x.sweeps.seed_medians);
    j.key("median_total_ms"); interval_json(j, x.total_ms.median);
    j.key("mean_total_ms"); interval_json(j, x.total_ms.mean);
    j.key("seed_median_total_ms").array(x.total_ms.seed_medians);
    j.end_object();
  }
  j.end_object();
  j.key("ratios").begin_array(JsonWriter::Layout::Lines);
  for (const auto& q : s.ratios) {
    j.begin_object();
    j.key("name").value(q.name);
    j.key("reference").value(q.reference);
    j.key("median_sweeps_to_tol"); interval_json(j, q.median_sweeps);
    j.key("mean_sweeps_to_tol"); interval_json(j, q.mean_sweeps);
    j.key("median_total_ms"); interval_json(j, q.median_total_ms);
    j.key("mean_total_ms"); interval_json(j, q.mean_total_ms);
    j.key("sweeps_distinguishable").value(q.sweeps_distinguishable());
    j.key("total_distinguishable").value(q.total_distinguishable());
    j.end_object();
  }
  j.end_array();
  j.end_object();
}

}  // namespace dc::bench
