// results.h5 of a bench run (layout: docs/bench.md).
#include "bench_report.hpp"
#include "dc/engine/scene.hpp"
#include "dc/io/h5.hpp"

namespace dc::bench {

std::string starter_group_name(const std::string& name) {
  std::string out;
  for (const char c : name) {
    if (c == '%') out += "%25";
    else if (c == '/') out += "%2F";
    else out += c;
  }
  return out;
}

void write_results_h5(const BenchResults& r, const Provenance& p, const std::string& path) {
  AtomicH5File out(path);
  H5File& f = out.file();
  f.set_attribute("/", "format", "deepcontact-bench-results");
  f.set_attribute<std::int32_t>("/", "format_version", 1);
  f.set_attribute("/", "mode", r.options.mode == Mode::Paired ? "paired" : "rollout");
  f.set_attribute("/", "solver", r.options.solver);
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
    f.write<double>(g + "/warmstart_ms", rec.warmstart_ms, {n});
    f.write<double>(g + "/oracle_ms", rec.oracle_ms, {n});
    f.write<double>(g + "/solve_ms", rec.solve_ms, {n});
    f.write<double>(g + "/ns_per_row_sweep", rec.sweep_ns_per_row, {n});
    std::vector<double> sweep_ms(n);
    for (hsize_t i = 0; i < n; ++i) sweep_ms[i] = rec.sweep_ns_per_row[i] * rec.rows[i] * 1e-6;
    f.write<double>(g + "/sweep_ms", sweep_ms, {n});
    f.write<double>(g + "/initial_error", rec.initial_error, {n});
    f.write<float>(g + "/theta", rec.theta, {n, K}, n > 0 ? compressed : H5DatasetOptions{});
    f.write<double>(g + "/residual", rec.residual, {n, B});
    f.write<double>(g + "/lambda_error", rec.lambda_error, {n, B});
    f.write<double>(g + "/penetration", rec.penetration, {n, B});
    f.write<double>(g + "/energy_error", rec.energy_error, {n, B});
  }
  f.write_strings("/warmstarter_names", names);
  f.write_strings("/warmstarter_groups", groups);
  out.commit();
}

}  // namespace dc::bench
