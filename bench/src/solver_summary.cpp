#include "dc/bench/solver_summary.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "dc/bench/json_writer.hpp"
#include "dc/bench/quantiles.hpp"
#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "report/report_format.hpp"

namespace dc::bench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// reached (0/1), ms to R, iterations to R, total ms, factorisations, outer passes, factorisations
// to R, Newton iterations to R
constexpr int kColumns = 8;

int comparison_cap(const BenchOptions& o) { return o.max_sweeps > 0 ? o.max_sweeps : o.sweeps; }

/// The pair's per-step columns, never-reached steps at the cap.
std::vector<std::vector<double>> pair_columns(const SolverPairRecord& p, int cap) {
  std::vector<std::vector<double>> c(kColumns);
  for (std::size_t k = 0; k < p.iterations_to_accuracy.size(); ++k) {
    const int it = p.iterations_to_accuracy[k];
    c[0].push_back(it >= 0 ? 1.0 : 0.0);
    c[1].push_back(p.ms_to_accuracy[k]);
    c[2].push_back(it >= 0 ? it : cap);
    c[3].push_back(p.total_ms[k]);
    c[4].push_back(std::max(0, p.factorizations[k]));
    c[5].push_back(std::max(0, p.outer_passes[k]));
    c[6].push_back(std::max(0, p.factorizations_to_accuracy[k]));
    c[7].push_back(std::max(0, p.newton_to_accuracy[k]));
  }
  return c;
}

/// Group offsets by seed: the steps of one seed are consecutive (the runner appends seed by seed).
std::vector<std::size_t> seed_offsets(const std::vector<std::uint64_t>& seed) {
  std::vector<std::size_t> off{0};
  for (std::size_t k = 1; k < seed.size(); ++k)
    if (seed[k] != seed[k - 1]) off.push_back(k);
  off.push_back(seed.size());
  return off;
}

std::vector<double> quotient(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> q(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) q[i] = a[i] / b[i];
  return q;
}

std::string interval_text(const Interval& x, const char* format) {
  if (!std::isfinite(x.estimate)) return "-";
  return fmt(format, x.estimate) + " [" + fmt(format, x.lo) + ", " + fmt(format, x.hi) + "]";
}

}  // namespace

std::vector<SolverPairSummary> summarise_solver_pairs(const BenchResults& r, const BootstrapDef& def) {
  std::vector<SolverPairSummary> out;
  if (r.pairs.empty()) return out;
  const int cap = comparison_cap(r.options);
  GroupedColumns all;
  all.offsets = seed_offsets(r.pairs[0].seed);
  for (const SolverPairRecord& p : r.pairs) {
    if (p.seed != r.pairs[0].seed)
      throw InvalidArgument("solver comparison: pair " + p.solver + "+" + p.starter + " ran on other steps");
    for (auto& c : pair_columns(p, cap)) all.columns.push_back(std::move(c));
  }
  const bool any = !r.pairs[0].seed.empty();
  Replicates rep;
  if (any) {
    Rng rng(def.seed);
    rep = hierarchical_bootstrap(all, def.resamples, rng);
  }
  std::size_t ref = r.pairs.size();  // pgs+builtin
  for (std::size_t i = 0; i < r.pairs.size(); ++i)
    if (r.pairs[i].solver == "pgs" && r.pairs[i].starter == "builtin") ref = i;
  auto col = [&](std::size_t pair, int c) { return pair * kColumns + static_cast<std::size_t>(c); };
  auto interval = [&](std::size_t pair, int c, bool mean) {
    if (!any) return Interval{};
    const auto& x = all.columns[col(pair, c)];
    return percentile_interval(mean ? mean_of(x) : median_of(x), mean ? rep.mean[col(pair, c)] : rep.median[col(pair, c)],
                               def.level);
  };
  for (std::size_t i = 0; i < r.pairs.size(); ++i) {
    SolverPairSummary s;
    s.solver = r.pairs[i].solver;
    s.starter = r.pairs[i].starter;
    s.steps = r.pairs[i].seed.size();
    s.reached_share = interval(i, 0, true);
    s.ms_to_accuracy = interval(i, 1, false);
    s.iterations_to_accuracy = interval(i, 2, false);
    s.total_ms = interval(i, 3, false);
    const auto counted = [](const std::vector<int>& v) {
      return !v.empty() && std::all_of(v.begin(), v.end(), [](int x) { return x >= 0; });
    };
    if (counted(r.pairs[i].factorizations)) {
      s.factorizations = interval(i, 4, false);
      s.p99_factorizations = quantile(all.columns[col(i, 4)], 0.99);
    }
    if (counted(r.pairs[i].outer_passes)) s.outer_passes = interval(i, 5, false);
    if (counted(r.pairs[i].factorizations_to_accuracy)) {
      s.factorizations_to_accuracy = interval(i, 6, false);
      s.p99_factorizations_to_accuracy = quantile(all.columns[col(i, 6)], 0.99);
    }
    if (counted(r.pairs[i].newton_to_accuracy)) s.newton_to_accuracy = interval(i, 7, false);
    if (any && ref < r.pairs.size()) {
      const double ref_total = median_of(all.columns[col(ref, 3)]);
      s.ms_to_accuracy_ratio = percentile_interval(s.ms_to_accuracy.estimate / ref_total,
                                                   quotient(rep.median[col(i, 1)], rep.median[col(ref, 3)]), def.level);
      s.total_ratio = percentile_interval(s.total_ms.estimate / ref_total,
                                          quotient(rep.median[col(i, 3)], rep.median[col(ref, 3)]), def.level);
    }
    out.push_back(s);
  }
  return out;
}

void solver_pairs_json(JsonWriter& j, const std::vector<SolverPairSummary>& s) {
  j.begin_object(JsonWriter::Layout::Lines);
  for (std::size_t i = 0; i < s.size();) {
    const std::string& solver = s[i].solver;
    j.key(solver).begin_object();
    for (; i < s.size() && s[i].solver == solver; ++i) {
      j.key(s[i].starter).begin_object();
      j.key("reached_share").value(s[i].reached_share.estimate);
      j.key("median_ms_to_accuracy").value(s[i].ms_to_accuracy.estimate);
      j.key("median_iterations_to_accuracy").value(s[i].iterations_to_accuracy.estimate);
      j.key("median_total_ms").value(s[i].total_ms.estimate);
      if (std::isfinite(s[i].factorizations.estimate)) {
        j.key("median_factorizations").value(s[i].factorizations.estimate);
        j.key("p99_factorizations").value(s[i].p99_factorizations);
      }
      if (std::isfinite(s[i].outer_passes.estimate)) j.key("median_outer_passes").value(s[i].outer_passes.estimate);
      if (std::isfinite(s[i].factorizations_to_accuracy.estimate)) {
        j.key("median_factorizations_to_accuracy").value(s[i].factorizations_to_accuracy.estimate);
        j.key("p99_factorizations_to_accuracy").value(s[i].p99_factorizations_to_accuracy);
      }
      if (std::isfinite(s[i].newton_to_accuracy.estimate))
        j.key("median_newton_to_accuracy").value(s[i].newton_to_accuracy.estimate);
      j.end_object();
    }
    j.end_object();
  }
  j.end_object();
}

std::string solver_pairs_markdown(const BenchResults& r, const std::vector<SolverPairSummary>& s) {
  if (s.empty()) return "";
  std::ostringstream md;
  const int cap = comparison_cap(r.options);
  md << "## Solver comparison\n\n";
  md << "Every solver started from every starter's guess λ⁰ on the same LCPs. Accuracy target R = "
     << fmt("%g", r.options.accuracy)
     << ": natural-map residual ≤ R · max_i(m_i |g|), the heaviest body's weight (the residual relative to the step's "
        "largest weight impulse max_i(m_i g Δt)). `reached` is the share of steps at R within "
     << cap << " iterations (a step that never gets there counts at the cap: " << cap
     << " iterations and the whole run's time). `ms to R` and `total ms` include the warm start; `total ms` is the "
        "solve to θ ≤ " << fmt("%g", r.options.tolerance)
     << " N (for newton-sparse: residual ≤ that). Medians over steps with bootstrap 95 % intervals (seeds, then "
        "steps); `/pgs+builtin` divides by pgs+builtin's median total ms. For the solvers that count them "
        "(newton-sparse, prox-newton): `fact. to R` (median [interval], p99 `p99 to R`) and `Newton to R` count the "
        "work up to the first checkpoint at R, where `ms to R` is taken (the whole run for a step that never gets "
        "there; prox-newton's Newton iterations exclude its lead stage's nncg sweeps); `factorisations` (median "
        "[interval], p99) and `outer passes` count the whole traced solve from λ⁰ to R/100 (where it stops).\n\n";
  md << "| solver | starter | reached | ms to R | iterations to R | total ms | ms to R /pgs+builtin | total /pgs+builtin "
        "| fact. to R | p99 to R | Newton to R | factorisations | p99 fact. | outer passes |\n";
  md << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& x : s)
    md << "| " << x.solver << " | " << x.starter << " | " << interval_text(x.reached_share, "%.2f") << " | "
       << interval_text(x.ms_to_accuracy, "%.3g") << " | " << interval_text(x.iterations_to_accuracy, "%.0f") << " | "
       << interval_text(x.total_ms, "%.3g") << " | " << interval_text(x.ms_to_accuracy_ratio, "%.3g") << " | "
       << interval_text(x.total_ratio, "%.3g") << " | " << interval_text(x.factorizations_to_accuracy, "%.0f") << " | "
       << (std::isfinite(x.p99_factorizations_to_accuracy) ? fmt("%.0f", x.p99_factorizations_to_accuracy)
                                                           : std::string("-"))
       << " | " << interval_text(x.newton_to_accuracy, "%.0f") << " | " << interval_text(x.factorizations, "%.0f") << " | "
       << (std::isfinite(x.p99_factorizations) ? fmt("%.0f", x.p99_factorizations) : std::string("-")) << " | "
       << interval_text(x.outer_passes, "%.0f") << " |\n";
  md << "\n";
  return md.str();
}

}  // namespace dc::bench
