#include "dc/bench/scale_sweep.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <sys/wait.h>

#include "dc/bench/json_writer.hpp"
#include "dc/bench/provenance.hpp"
#include "report/report_format.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/core/install_paths.hpp"

namespace dc::bench {

int scene_body_count(const WorldDef& def) {
  int n = def.bodies.count + static_cast<int>(def.body.size());
  if (def.inflow.active()) n += static_cast<int>(std::ceil((def.inflow.stop - def.inflow.start) * def.inflow.rate - 1e-9));
  return n;
}

WorldDef scale_scene(const WorldDef& def, int n, ScaleAxis axis) {
  const int n0 = scene_body_count(def);
  if (n < 1) throw ConfigError("--scale: body counts must be >= 1, got " + std::to_string(n));
  if (n0 < 1) throw ConfigError("--scale: the scene has no bodies to scale");
  const double q = static_cast<double>(n) / n0;
  const double fx = axis == ScaleAxis::Both ? std::sqrt(q) : 1.0;
  const double fy = axis == ScaleAxis::Both ? std::sqrt(q) : q;
  WorldDef d = def;
  d.world.width *= fx;
  d.world.height *= fy;
  d.bodies.count = static_cast<int>(std::lround(def.bodies.count * q));
  d.bodies.mean = {def.bodies.mean.x * fx, def.bodies.mean.y * fy};
  d.bodies.sigma *= std::sqrt(fx * fy);
  auto stretch = [&](std::array<double, 4>& r) {
    if (r[0] == 0 && r[1] == 0 && r[2] == 0 && r[3] == 0) return;
    r = {r[0] * fx, r[1] * fy, r[2] * fx, r[3] * fy};
  };
  stretch(d.bodies.region);
  stretch(d.inflow.region);
  d.inflow.rate *= q;
  for (BodyDef& b : d.body) b.position = {b.position.x * fx, b.position.y * fy};
  d.validate();
  return d;
}

std::vector<ScalePoint> run_scale_sweep(const BenchOptions& base, const std::vector<int>& counts, ScaleAxis axis,
                                        int no_oracle_from, const WarmStarterRegistry& registry,
                                        const ProgressFn& progress) {
  std::vector<ScalePoint> out;
  for (const int n : counts) {
    ScalePoint p;
    p.n = n;
    BenchOptions o = base;
    o.scene = scale_scene(base.scene, n, axis);
    p.bodies = scene_body_count(o.scene);
    p.width = o.scene.world.width;
    p.height = o.scene.world.height;
    if (no_oracle_from > 0 && p.bodies >= no_oracle_from) {
      o.oracle = false;
      std::vector<std::string> kept;
      for (const auto& name : o.warmstarts)
        if (!registry.make(name, o.env)->uses_oracle()) kept.push_back(name);
      o.warmstarts = kept;
    }
    p.results = run_bench(o, registry, progress);
    p.summary = summarise(p.results);
    out.push_back(std::move(p));
  }
  return out;
}

namespace {

std::string never_or(double v, int cap) { return v > cap ? "never" : fmt("%.0f", v); }

}  // namespace

std::string format_scale_table(const std::vector<ScalePoint>& points, bool md) {
  std::vector<std::vector<std::string>> rows;
  rows.push_back({"N", "box", "oracle", "warm starter", "sweeps to tol (median)", "never", "resid@budget", "resid@cap",
                  "sweeps high cap", "never high cap", "warmstart ms", "total ms", "steps"});
  for (const auto& p : points) {
    const auto& o = p.results.options;
    for (const auto& x : p.summary) {
      rows.push_back({std::to_string(p.bodies), fmt("%.1f", p.width) + "x" + fmt("%.1f", p.height), o.oracle ? "yes" : "skipped",
                      x.name, never_or(x.median_sweeps_to_tol, o.sweeps), fmt("%.1f%%", 100 * x.unconverged_share),
                      fmt("%.2e", x.residual_at_budget), fmt("%.2e", x.residual_at_cap),
                      o.max_sweeps > 0 ? never_or(x.median_sweeps_high, o.max_sweeps) : "-",
                      o.max_sweeps > 0 ? fmt("%.1f%%", 100 * x.unconverged_share_high) : "-", fmt("%.4f", x.warmstart_ms),
                      fmt("%.3f", x.total_ms),
                      std::to_string(p.results.starters.empty() ? 0 : p.results.starters[0].sweeps_to_tol.size())});
    }
  }
  std::vector<std::size_t> w(rows[0].size(), 0);
  for (const auto& row : rows)
    for (std::size_t c = 0; c < row.size(); ++c) w[c] = std::max(w[c], row[c].size());
  std::ostringstream os;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t c = 0; c < rows[i].size(); ++c) {
      if (md) os << "| " << rows[i][c] << ' ';
      else os << (c ? "  " : "") << rows[i][c] << std::string(w[c] - rows[i][c].size(), ' ');
    }
    os << (md ? "|\n" : "\n");
    if (md && i == 0) {
      for (std::size_t c = 0; c < rows[i].size(); ++c) os << (c ? "|---:" : "|---");
      os << "|\n";
    }
  }
  return os.str();
}

std::vector<std::string> write_scale_report(const std::vector<ScalePoint>& points, ScaleAxis axis,
                                            const std::string& dir_text) {
  namespace fs = std::filesystem;
  const fs::path dir(dir_text);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(dir_text + ": cannot create the output directory: " + ec.message());
  std::vector<std::string> files;
  // CSV: one row per (N, starter); what scale_plot.py reads.
  std::ostringstream csv;
  csv << "bodies,width,height,oracle,starter,median_sweeps_to_tol,unconverged_share,residual_at_budget,"
         "residual_at_cap,median_sweeps_high_cap,unconverged_share_high_cap,warmstart_ms,total_ms,sweeps,max_sweeps,"
         "budget\n";
  JsonWriter j;
  j.begin_object(JsonWriter::Layout::Lines);
  j.key("axis").value(axis == ScaleAxis::Both ? "both" : "height");
  j.key("points").begin_array(JsonWriter::Layout::Lines);
  for (const auto& p : points) {
    const auto& o = p.results.options;
    for (const auto& x : p.summary) {
      csv << p.bodies << ',' << p.width << ',' << p.height << ',' << (o.oracle ? 1 : 0) << ',' << x.name << ','
          << x.median_sweeps_to_tol << ',' << x.unconverged_share << ',' << x.residual_at_budget << ','
          << x.residual_at_cap << ',' << (o.max_sweeps > 0 ? x.median_sweeps_high : 0) << ','
          << x.unconverged_share_high << ',' << x.warmstart_ms << ',' << x.total_ms << ',' << o.sweeps << ','
          << o.max_sweeps << ',' << o.budget << '\n';
      j.begin_object();
      j.key("bodies").value(p.bodies);
      j.key("width").value(p.width);
      j.key("height").value(p.height);
      j.key("oracle").value(o.oracle);
      j.key("starter").value(x.name);
      j.key("median_sweeps_to_tol").value(x.median_sweeps_to_tol);
      j.key("unconverged_share").value(x.unconverged_share);
      j.key("residual_at_budget").value(x.residual_at_budget);
      j.key("residual_at_cap").value(x.residual_at_cap);
      j.key("median_sweeps_high_cap").value(x.median_sweeps_high);
      j.key("unconverged_share_high_cap").value(x.unconverged_share_high);
      j.key("warmstart_ms").value(x.warmstart_ms);
      j.key("total_ms").value(x.total_ms);
      j.end_object();
    }
  }
  j.end_array();
  const Provenance prov = collect_provenance();
  j.key("git").value(prov.git);
  j.key("machine").value(prov.machine);
  j.end_object();
  write_file_atomically((dir / "scale.csv").string(), csv.str());
  files.push_back((dir / "scale.csv").string());
  write_file_atomically((dir / "scale.json").string(), j.str());
  files.push_back((dir / "scale.json").string());

  const char* py_env = std::getenv("DC_BENCH_PYTHON");
  const std::string py = py_env && *py_env ? py_env : "/usr/bin/python3";
  const std::string script = data_path("bench/plots/scale_plot.py").string();
  const std::string log = (dir / "scale_plot.log").string();
  const std::string cmd = "'" + py + "' '" + script + "' '" + (dir / "scale.csv").string() + "' '" +
                          (dir / "scale.png").string() + "' >'" + log + "' 2>&1";
  const int status = std::system(cmd.c_str());
  const bool plotted = status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::exists(dir / "scale.png");
  if (plotted) files.push_back((dir / "scale.png").string());

  const auto& o0 = points.empty() ? BenchOptions{} : points.front().results.options;
  std::ostringstream md;
  md << "# DeepContact size sweep: family `" << (o0.family.empty() ? "seed" : o0.family) << "`\n\n";
  md << "The scene scaled to N bodies "
     << (axis == ScaleAxis::Both ? "keeping its aspect ratio and filling density (both box sides × √(N/N₀))"
                                 : "keeping its width (height × N/N₀: a deeper pile)")
     << "; mode " << (o0.mode == Mode::Paired ? "paired" : "rollout") << ", " << o0.sweeps << " sweeps, tol "
     << o0.tolerance << " N, seeds";
  for (auto s : o0.seeds) md << ' ' << s;
  md << ". `resid@budget` / `resid@cap`: median natural-map residual [N] after " << o0.budget << " / " << o0.sweeps
     << " sweeps";
  if (o0.max_sweeps > 0) md << "; `sweeps high cap`: sweeps to tol when a step may run up to " << o0.max_sweeps << " sweeps";
  md << ". Medians over steps; never = the cap was reached. Rows with oracle **skipped**: the reference trajectory "
        "was advanced with builtin + PGS to tol/100 (no tight oracle: too slow at this size) and oracle starters did "
        "not run.\n\n";
  md << format_scale_table(points, true) << "\n";
  md << (plotted ? "![size sweep](scale.png)\n\n" : "The plot failed: see scale_plot.log.\n\n");
  md << "- git: `" << prov.git << "`\n- machine: " << prov.machine << "\n- date: " << prov.date_utc << "\n";
  write_file_atomically((dir / "scale.md").string(), md.str());
  files.push_back((dir / "scale.md").string());
  if (!plotted) throw IoError(dir_text + "/scale.png: the plot script failed (its output: " + log + ")");
  return files;
}

}  // namespace dc::bench
