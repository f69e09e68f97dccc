// results.h5 of a bench run (layout: docs/bench.md).
#include <algorithm>
#include <span>
#include <vector>

#include "report/bench_statistics_report.hpp"
#include "dc/bench/bench_report.hpp"
#include "dc/bench/solver_summary.hpp"
#include "dc/engine/scene.hpp"
#include "dc/io/h5.hpp"

namespace dc::bench {
namespace {

/// Quartiles of one column of n values (reordered in place): linear interpolation between order
/// statistics, as numpy's percentile.
void column_quartiles(std::span<float> column, double* out) {
  const auto n = static_cast<std::ptrdiff_t>(column.size());
  for (int q = 0; q < 3; ++q) {  // selection, not a sort: O(n) per quantile
    const double pos = 0.25 * (q + 1) * static_cast<double>(n - 1);
    const auto lo = static_cast<std::ptrdiff_t>(pos);
    std::nth_element(column.begin(), column.begin() + lo, column.end());
    const double at_lo = column[static_cast<std::size_t>(lo)];
    const double at_hi = lo + 1 < n ? *std::min_element(column.begin() + lo + 1, column.end()) : at_lo;
    out[q] = at_lo + (pos - static_cast<double>(lo)) * (at_hi - at_lo);
  }
}

/// Per sweep k: the 25th, 50th and 75th percentile of θ_k over the n steps, row-major K × 3.
/// What the report's convergence plot draws, kept when the full θ is not. The rows are read
/// from disk a block of sweeps at a time (~8 MB of columns in RAM, however many steps).
std::vector<double> theta_quartiles(const ThetaRows& theta, hsize_t K) {
  const std::size_t n = theta.rows();
  std::vector<double> out(K * 3, 0.0);
  if (n == 0) return out;
  const std::size_t block = std::clamp<std::size_t>((std::size_t{2} << 20) / n, 1, K);  // sweeps per pass
  std::vector<float> cols(n * block), column(n);  // cols: step-major n × block
  for (std::size_t k0 = 0; k0 < K; k0 += block) {
    const std::size_t w = std::min<std::size_t>(block, K - k0);
    for (std::size_t i = 0; i < n; ++i) theta.read_row(i, std::span<float>(cols).subspan(i * w, w), k0);
    for (std::size_t k = 0; k < w; ++k) {
      for (std::size_t i = 0; i < n; ++i) column[i] = cols[i * w + k];
      column_quartiles(column, &out[(k0 + k) * 3]);
    }
  }
  return out;
}

/// /warmstarters/NAME/theta (n × K, gzip), written a block of steps at a time.
void write_theta(H5File& f, const std::string& path, const ThetaRows& theta, hsize_t K) {
  const hsize_t n = theta.rows();
  if (n == 0) {
    f.write<float>(path, std::vector<float>{}, {0, K});
    return;
  }
  const H5DatasetOptions compressed{.extendible = false, .chunk_rows = 0, .deflate = 4};
  f.create_dataset<float>(path, {n, K}, compressed);
  const std::size_t block = std::clamp<std::size_t>((std::size_t{2} << 20) / K, 1, n);  // steps per write
  std::vector<float> rows(block * K);
  for (std::size_t i0 = 0; i0 < n; i0 += block) {
    const std::size_t m = std::min<std::size_t>(block, n - i0);
    for (std::size_t i = 0; i < m; ++i) theta.read_row(i0 + i, std::span<float>(rows).subspan(i * K, K));
    f.write_rows<float>(path, i0, std::span<const float>(rows.data(), m * K));
  }
}

}  // namespace

std::string starter_group_name(const std::string& name) {
  std::string out;
  for (const char c : name) {
    if (c == '%') out += "%25";
    else if (c == '/') out += "%2F";
    else out += c;
  }
  return out;
}

namespace {

/// The solver comparison (docs/bench.md "results.h5"): /solvers with the target and the cap, the
/// pairs' names in /solvers/pair_names (SOLVER+STARTER) and groups in /solvers/pair_groups, and
/// per pair its per-step figures and accuracy traces (ragged: step k's points are
/// trace_offsets[k] … trace_offsets[k+1]−1).
void write_solver_pairs_h5(H5File& f, const BenchResults& r) {
  f.create_group("/solvers");
  f.set_attribute<double>("/solvers", "accuracy", r.options.accuracy);
  f.set_attribute<std::int32_t>("/solvers", "cap", r.options.max_sweeps > 0 ? r.options.max_sweeps : r.options.sweeps);
  std::vector<std::string> names, groups;
  for (const SolverPairRecord& p : r.pairs) {
    names.push_back(p.solver + "+" + p.starter);
    groups.push_back(starter_group_name(names.back()));
    const std::string g = "/solvers/" + groups.back();
    const hsize_t n = p.seed.size(), t = p.trace_ms.size();
    f.create_group(g);
    f.set_attribute(g, "solver", p.solver);
    f.set_attribute(g, "starter", p.starter);
    const std::vector<std::int64_t> seed(p.seed.begin(), p.seed.end());
    const std::vector<std::int32_t> it(p.iterations_to_accuracy.begin(), p.iterations_to_accuracy.end());
    const std::vector<std::int64_t> off(p.trace_offsets.begin(), p.trace_offsets.end());
    f.write<std::int64_t>(g + "/seed", seed, {n});
    f.write<std::int32_t>(g + "/iterations_to_accuracy", it, {n});
    f.write<double>(g + "/ms_to_accuracy", p.ms_to_accuracy, {n});
    f.write<double>(g + "/total_ms", p.total_ms, {n});
    f.write<double>(g + "/final_accuracy", p.final_accuracy, {n});
    f.write<double>(g + "/weight_scale", p.weight_scale, {n});
    const std::vector<std::int32_t> fac(p.factorizations.begin(), p.factorizations.end());
    const std::vector<std::int32_t> outer(p.outer_passes.begin(), p.outer_passes.end());
    f.write<std::int32_t>(g + "/factorizations", fac, {n});
    f.write<std::int32_t>(g + "/outer_passes", outer, {n});
    const std::vector<std::int32_t> fac_r(p.factorizations_to_accuracy.begin(), p.factorizations_to_accuracy.end());
    const std::vector<std::int32_t> newton_r(p.newton_to_accuracy.begin(), p.newton_to_accuracy.end());
    f.write<std::int32_t>(g + "/factorizations_to_accuracy", fac_r, {n});
    f.write<std::int32_t>(g + "/newton_to_accuracy", newton_r, {n});
    f.write<std::int64_t>(g + "/trace_offsets", off, {off.size()});
    f.write<double>(g + "/trace_ms", p.trace_ms, {t});
    f.write<double>(g + "/trace_accuracy", p.trace_accuracy, {t});
  }
  f.write_strings("/solvers/pair_names", names);
  f.write_strings("/solvers/pair_groups", groups);
  // The summary with its bootstrap intervals: (pairs × 10 × 3), figures in the order of
  // /solvers/interval_figures, each (estimate, lo, hi); NaN where a pair does not count a figure
  // (factorisations and outer passes: only the solvers that count them).
  const std::vector<SolverPairSummary> sum = summarise_solver_pairs(r);
  std::vector<double> iv;
  for (const SolverPairSummary& x : sum)
    for (const Interval& v : {x.reached_share, x.ms_to_accuracy, x.iterations_to_accuracy, x.total_ms,
                              x.ms_to_accuracy_ratio, x.total_ratio, x.factorizations, x.outer_passes,
                              x.factorizations_to_accuracy, x.newton_to_accuracy})
      iv.insert(iv.end(), {v.estimate, v.lo, v.hi});
  f.write<double>("/solvers/intervals", iv, {sum.size(), 10, 3});
  f.write_strings("/solvers/interval_figures", {"reached_share", "median_ms_to_accuracy", "median_iterations_to_accuracy",
                                                "median_total_ms", "ms_to_accuracy_over_pgs_builtin_total",
                                                "total_over_pgs_builtin_total", "median_factorizations",
                                                "median_outer_passes", "median_factorizations_to_accuracy",
                                                "median_newton_to_accuracy"});
}

}  // namespace

void write_results_h5(const BenchResults& r, const Provenance& p, const std::string& path,
                      const BenchStatistics* stats) {
  AtomicH5File out(path);
  H5File& f = out.file();
  f.set_attribute("/", "format", "deepcontact-bench-results");
  f.set_attribute<std::int32_t>("/", "format_version", 1);
  f.set_attribute("/", "mode", r.options.mode == Mode::Paired ? "paired" : "rollout");
  f.set_attribute("/", "solver", to_string(r.options.solver));
  f.set_attribute<std::int32_t>("/", "sweeps", r.options.sweeps);
  f.set_attribute<double>("/", "tolerance", r.options.tolerance);
  f.set_attribute("/", "scene", scene_to_toml(r.options.scene));
  f.set_attribute("/", "git", p.git);
  f.set_attribute("/", "build", p.build);
  f.set_attribute("/", "machine", p.machine);
  f.set_attribute("/", "date", p.date_utc);
  f.set_attribute<double>("/", "wall_seconds", r.wall_seconds);
  f.set_attribute<std::int32_t>("/", "skipped_steps", r.skipped_steps);
  {
    std::vector<std::int64_t> seeds(r.options.seeds.begin(), r.options.seeds.end());
    f.set_attribute_array<std::int64_t>("/", "seeds", seeds);
  }
  const std::vector<std::int32_t> budgets(r.budgets.begin(), r.budgets.end());
  f.write<std::int32_t>("/budgets", budgets, {budgets.size()});

  // Shared per-step figures of the paired mode (the reference trajectory).
  const hsize_t S = r.step_index.size();
  std::vector<std::int64_t> seed(r.step_seed.begin(), r.step_seed.end());
  std::vector<std::int32_t> idx(r.step_index.begin(), r.step_index.end());
  std::vector<std::int32_t> rows(r.step_rows.begin(), r.step_rows.end());
  f.write<std::int64_t>("/steps/seed", seed, {S});
  f.write<std::int32_t>("/steps/index", idx, {S});
  if (rows.size() == S) f.write<std::int32_t>("/steps/rows", rows, {S});
  if (r.oracle_ms.size() == S) {
    f.write<double>("/steps/oracle_ms", r.oracle_ms, {S});
    f.write<double>("/steps/oracle_residual", r.oracle_residual, {S});
  }
  if (r.collide_ms.size() == S && r.assemble_ms.size() == S && r.integrate_ms.size() == S) {
    f.write<double>("/steps/collide_ms", r.collide_ms, {S});
    f.write<double>("/steps/assemble_ms", r.assemble_ms, {S});
    f.write<double>("/steps/integrate_ms", r.integrate_ms, {S});
  }

  std::vector<std::string> names, groups;
  const H5DatasetOptions compressed{.extendible = false, .chunk_rows = 0, .deflate = 4};
  for (const StarterRecord& rec : r.starters) {
    names.push_back(rec.name);
    groups.push_back(starter_group_name(rec.name));
    const std::string g = "/warmstarters/" + groups.back();
    const hsize_t n = rec.sweeps_to_tol.size(), B = r.budgets.size(), K = static_cast<hsize_t>(r.options.sweeps);
    f.create_group(g);
    f.set_attribute<std::int32_t>(g, "uses_oracle", rec.uses_oracle ? 1 : 0);
    f.set_attribute(g, "name", rec.name);
    std::vector<std::int64_t> s(rec.seed.begin(), rec.seed.end());
    std::vector<std::int32_t> st(rec.step.begin(), rec.step.end()), rw(rec.rows.begin(), rec.rows.end()),
        tt(rec.sweeps_to_tol.begin(), rec.sweeps_to_tol.end());
    f.write<std::int64_t>(g + "/seed", s, {n});
    f.write<std::int32_t>(g + "/step", st, {n});
    f.write<std::int32_t>(g + "/rows", rw, {n});
    f.write<std::int32_t>(g + "/sweeps_to_tol", tt, {n});
    if (!rec.sweeps_to_tol_high.empty()) {
      const std::vector<std::int32_t> hi(rec.sweeps_to_tol_high.begin(), rec.sweeps_to_tol_high.end());
      f.write<std::int32_t>(g + "/sweeps_to_tol_high", hi, {n});
      f.set_attribute<std::int32_t>(g, "max_sweeps", r.options.max_sweeps);
    }
    f.write<double>(g + "/warmstart_ms", rec.warmstart_ms, {n});
    f.write<double>(g + "/oracle_ms", rec.oracle_ms, {n});
    f.write<double>(g + "/solve_ms", rec.solve_ms, {n});
    f.write<double>(g + "/ns_per_row_sweep", rec.sweep_ns_per_row, {n});
    std::vector<double> sweep_ms(n);
    for (hsize_t i = 0; i < n; ++i) sweep_ms[i] = rec.sweep_ns_per_row[i] * rec.rows[i] * 1e-6;
    f.write<double>(g + "/sweep_ms", sweep_ms, {n});
    f.write<double>(g + "/initial_error", rec.initial_error, {n});
    if (r.options.keep_theta) write_theta(f, g + "/theta", rec.theta, K);
    f.write<double>(g + "/theta_quartiles", theta_quartiles(rec.theta, K), {K, 3});
    // gzip + shuffle halves these (45 → 24 MB for the default bench): with θ opt-in, results.h5
    // stays under 50 MB.
    const H5DatasetOptions per_budget = n > 0 && B > 0 ? compressed : H5DatasetOptions{};
    f.write<double>(g + "/residual", rec.residual, {n, B}, per_budget);
    f.write<double>(g + "/lambda_error", rec.lambda_error, {n, B}, per_budget);
    f.write<double>(g + "/penetration", rec.penetration, {n, B}, per_budget);
    f.write<double>(g + "/energy_error", rec.energy_error, {n, B}, per_budget);
  }
  f.write_strings("/warmstarter_names", names);
  f.write_strings("/warmstarter_groups", groups);
  if (stats) write_statistics_h5(f, *stats);
  if (!r.pairs.empty()) write_solver_pairs_h5(f, r);
  out.commit();
}

}  // namespace dc::bench

namespace dc::bench {

void write_statistics_h5(H5File& f, const BenchStatistics& s) {
  const std::string g = "/statistics";
  f.create_group(g);
  f.set_attribute(g, "method", "hierarchical percentile bootstrap: seeds with replacement, then steps within each "
                               "drawn seed");
  f.set_attribute<std::int32_t>(g, "resamples", s.def.resamples);
  f.set_attribute<double>(g, "level", s.def.level);
  f.set_attribute<std::int64_t>(g, "rng_seed", static_cast<std::int64_t>(s.def.seed));
  f.set_attribute<std::int32_t>(g, "paired", s.paired ? 1 : 0);
  f.set_attribute<std::int32_t>(g, "never_counts_as", s.sweeps + 1);
  const std::vector<std::int64_t> seeds(s.seeds.begin(), s.seeds.end());
  f.write<std::int64_t>(g + "/seeds", seeds, {seeds.size()});
  // (estimate, lo, hi) per row.
  auto triples = [&](const std::string& path, std::size_t n, auto&& get) {
    std::vector<double> v;
    for (std::size_t i = 0; i < n; ++i) {
      const Interval x = get(i);
      v.insert(v.end(), {x.estimate, x.lo, x.hi});
    }
    f.write<double>(g + "/" + path, v, {n, 3});
  };
  const std::size_t W = s.starters.size(), G = s.seeds.size(), R = s.ratios.size();
  if (W > 0) {
    std::vector<std::string> names;
    std::vector<double> seed_sweeps, seed_total;
    for (const auto& x : s.starters) {
      names.push_back(x.name);
      seed_sweeps.insert(seed_sweeps.end(), x.sweeps.seed_medians.begin(), x.sweeps.seed_medians.end());
      seed_total.insert(seed_total.end(), x.total_ms.seed_medians.begin(), x.total_ms.seed_medians.end());
    }
    f.write_strings(g + "/starters", names);
    triples("median_sweeps_to_tol", W, [&](std::size_t i) { return s.starters[i].sweeps.median; });
    triples("mean_sweeps_to_tol", W, [&](std::size_t i) { return s.starters[i].sweeps.mean; });
    triples("median_total_ms", W, [&](std::size_t i) { return s.starters[i].total_ms.median; });
    triples("mean_total_ms", W, [&](std::size_t i) { return s.starters[i].total_ms.mean; });
    if (G > 0) {
      f.write<double>(g + "/seed_median_sweeps_to_tol", seed_sweeps, {W, G});
      f.write<double>(g + "/seed_median_total_ms", seed_total, {W, G});
    }
  }
  if (R > 0) {
    std::vector<std::string> num, ref;
    std::vector<std::int32_t> dist_sweeps, dist_total;
    for (const auto& q : s.ratios) {
      num.push_back(q.name);
      ref.push_back(q.reference);
      dist_sweeps.push_back(q.sweeps_distinguishable() ? 1 : 0);
      dist_total.push_back(q.total_distinguishable() ? 1 : 0);
    }
    f.write_strings(g + "/ratio_name", num);
    f.write_strings(g + "/ratio_reference", ref);
    triples("ratio_median_sweeps_to_tol", R, [&](std::size_t i) { return s.ratios[i].median_sweeps; });
    triples("ratio_mean_sweeps_to_tol", R, [&](std::size_t i) { return s.ratios[i].mean_sweeps; });
    triples("ratio_median_total_ms", R, [&](std::size_t i) { return s.ratios[i].median_total_ms; });
    triples("ratio_mean_total_ms", R, [&](std::size_t i) { return s.ratios[i].mean_total_ms; });
    f.write<std::int32_t>(g + "/ratio_sweeps_distinguishable", dist_sweeps, {R});
    f.write<std::int32_t>(g + "/ratio_total_distinguishable", dist_total, {R});
  }
}

}  // namespace dc::bench
