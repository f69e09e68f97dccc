#include "bench_statistics_report.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "bench_report.hpp"
#include "provenance.hpp"

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

std::string interval_json(const Interval& x) {
  return "{\"estimate\": " + json_number(x.estimate) + ", \"lo\": " + json_number(x.lo) + ", \"hi\": " +
         json_number(x.hi) + "}";
}

std::string array_json(const std::vector<double>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + json_number(v[i]);
  return out + "]";
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

std::string statistics_json(const BenchStatistics& s) {
  const int sweeps = s.sweeps;
  std::ostringstream os;
  os << "{\"method\": \"hierarchical percentile bootstrap: seeds with replacement, then steps within each drawn "
        "seed\", \"resamples\": "
     << s.def.resamples << ", \"level\": " << json_number(s.def.level) << ", \"rng_seed\": " << s.def.seed
     << ", \"paired\": " << (s.paired ? "true" : "false") << ", \"never_counts_as\": " << sweeps + 1
     << ", \"seeds\": [";
  for (std::size_t i = 0; i < s.seeds.size(); ++i) os << (i ? ", " : "") << s.seeds[i];
  os << "],\n    \"warmstarters\": {";
  for (std::size_t i = 0; i < s.starters.size(); ++i) {
    const auto& x = s.starters[i];
    os << (i ? ",\n      " : "\n      ") << "\"" << json_escape(x.name) << "\": {\"steps\": " << x.steps
       << ", \"median_sweeps_to_tol\": " << interval_json(x.sweeps.median)
       << ", \"mean_sweeps_to_tol\": " << interval_json(x.sweeps.mean)
       << ", \"seed_median_sweeps_to_tol\": " << array_json(x.sweeps.seed_medians)
       << ", \"median_total_ms\": " << interval_json(x.total_ms.median)
       << ", \"mean_total_ms\": " << interval_json(x.total_ms.mean)
       << ", \"seed_median_total_ms\": " << array_json(x.total_ms.seed_medians) << "}";
  }
  os << "},\n    \"ratios\": [";
  for (std::size_t i = 0; i < s.ratios.size(); ++i) {
    const auto& q = s.ratios[i];
    os << (i ? ",\n      " : "\n      ") << "{\"name\": \"" << json_escape(q.name) << "\", \"reference\": \""
       << json_escape(q.reference) << "\", \"median_sweeps_to_tol\": " << interval_json(q.median_sweeps)
       << ", \"mean_sweeps_to_tol\": " << interval_json(q.mean_sweeps)
       << ", \"median_total_ms\": " << interval_json(q.median_total_ms)
       << ", \"mean_total_ms\": " << interval_json(q.mean_total_ms)
       << ", \"sweeps_distinguishable\": " << (q.sweeps_distinguishable() ? "true" : "false")
       << ", \"total_distinguishable\": " << (q.total_distinguishable() ? "true" : "false") << "}";
  }
  os << "]}";
  return os.str();
}

}  // namespace dc::bench
