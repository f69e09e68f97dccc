#include "bench_report.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dc/engine/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/io/atomic_file.hpp"

namespace dc::bench {
namespace {

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

const StarterSummary* find(const std::vector<StarterSummary>& s, const std::string& name) {
  for (const auto& x : s)
    if (x.name == name) return &x;
  return nullptr;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  write_file_atomically(path.string(), text);
}

std::string sweeps_text(const StarterSummary& s, int sweeps) {
  if (s.median_sweeps_to_tol > sweeps) return "never";
  return fmt("%.0f", s.median_sweeps_to_tol);
}

}  // namespace

std::string thesis_reference(const std::string& starter) {
  const std::string base = starter.substr(0, starter.find(':'));
  if (base == "copy") return "0-20";
  if (base == "sph") return "~135";
  if (base == "builtin") return "230-245";
  if (base == "cnn") return "310-420";
  if (base == "zero") return "400-420";
  return "";
}

std::string format_table(const BenchResults& r, const std::vector<StarterSummary>& s, bool md) {
  const StarterSummary* zero = find(s, "zero");
  const int N = r.options.sweeps;
  std::vector<std::vector<std::string>> rows;
  rows.push_back({"warm starter", "sweeps to tol (median)", "q1-q3", "/zero", "never", "warmstart ms",
                  "oracle ms", "solve ms", "total ms", "total /zero", "theses"});
  for (const auto& x : s) {
    std::string q = x.sweeps_to_tol.q1 > N ? "never" : fmt("%.0f", x.sweeps_to_tol.q1);
    q += "-";
    q += x.sweeps_to_tol.q3 > N ? "never" : fmt("%.0f", x.sweeps_to_tol.q3);
    const bool has_zero = zero && zero->median_sweeps_to_tol > 0;
    rows.push_back({x.name + (x.uses_oracle ? " *" : ""), sweeps_text(x, N), q,
                    has_zero ? fmt("%.3f", x.median_sweeps_to_tol / zero->median_sweeps_to_tol) : "",
                    fmt("%.1f%%", 100 * x.unconverged_share), fmt("%.4f", x.warmstart_ms),
                    x.uses_oracle ? fmt("%.3f", x.oracle_ms) : "-", fmt("%.3f", x.solve_ms),
                    fmt("%.3f", x.total_ms), zero && zero->total_ms > 0 ? fmt("%.3f", x.total_ms / zero->total_ms) : "",
                    thesis_reference(x.name)});
  }
  std::vector<std::size_t> w(rows[0].size(), 0);
  for (const auto& row : rows)
    for (std::size_t c = 0; c < row.size(); ++c) w[c] = std::max(w[c], row[c].size());
  std::ostringstream os;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t c = 0; c < rows[i].size(); ++c) {
      const std::string& cell = rows[i][c];
      if (md) {
        os << "| " << cell << ' ';
      } else {
        os << (c ? "  " : "") << cell << std::string(w[c] - cell.size(), ' ');
      }
    }
    os << (md ? "|\n" : "\n");
    if (md && i == 0) {
      for (std::size_t c = 0; c < rows[i].size(); ++c) os << (c ? "|---:" : "|---");
      os << "|\n";
    }
  }
  return os.str();
}

std::string summary_json(const BenchResults& r, const std::vector<StarterSummary>& s, const Provenance& p) {
  const StarterSummary* zero = find(s, "zero");
  std::ostringstream os;
  os << "{\n  \"warmstarters\": {\n";
  for (std::size_t i = 0; i < s.size(); ++i) {
    const auto& x = s[i];
    const bool never = x.median_sweeps_to_tol > r.options.sweeps;
    os << "    \"" << json_escape(x.name) << "\": {"
       << "\"median_sweeps_to_tol\": " << (never ? "null" : json_number(x.median_sweeps_to_tol))
       << ", \"q1_sweeps_to_tol\": " << (x.sweeps_to_tol.q1 > r.options.sweeps ? "null" : json_number(x.sweeps_to_tol.q1))
       << ", \"q3_sweeps_to_tol\": " << (x.sweeps_to_tol.q3 > r.options.sweeps ? "null" : json_number(x.sweeps_to_tol.q3))
       << ", \"unconverged_share\": " << json_number(x.unconverged_share)
       << ", \"warmstart_ms\": " << json_number(x.warmstart_ms)
       << ", \"oracle_ms\": " << json_number(x.uses_oracle ? x.oracle_ms : 0.0)
       << ", \"solve_ms\": " << json_number(x.solve_ms)
       << ", \"total_ms\": " << json_number(x.total_ms)
       << ", \"ns_per_row_sweep\": " << json_number(x.ns_per_row_sweep)
       << ", \"initial_error\": " << json_number(x.initial_error)
       << ", \"uses_oracle\": " << (x.uses_oracle ? "true" : "false")
       << ", \"sweeps_ratio_to_zero\": "
       << (zero && zero->median_sweeps_to_tol > 0 && !never ? json_number(x.median_sweeps_to_tol / zero->median_sweeps_to_tol) : "null")
       << ", \"total_ratio_to_zero\": " << (zero && zero->total_ms > 0 ? json_number(x.total_ms / zero->total_ms) : "null")
       << ", \"theses\": \"" << thesis_reference(x.name) << "\"}" << (i + 1 < s.size() ? "," : "") << "\n";
  }
  os << "  },\n";
  os << "  \"scene\": \"" << json_escape(scene_to_toml(r.options.scene)) << "\",\n";
  os << "  \"seeds\": [";
  for (std::size_t i = 0; i < r.options.seeds.size(); ++i) os << (i ? ", " : "") << r.options.seeds[i];
  os << "],\n";
  os << "  \"mode\": \"" << (r.options.mode == Mode::Paired ? "paired" : "rollout") << "\",\n";
  os << "  \"solver\": \"" << json_escape(r.options.solver) << "\",\n";
  os << "  \"sweeps\": " << r.options.sweeps << ",\n";
  os << "  \"tolerance\": " << json_number(r.options.tolerance) << ",\n";
  os << "  \"evaluated_steps\": " << (r.starters.empty() ? 0 : r.starters[0].sweeps_to_tol.size()) << ",\n";
  os << "  \"skipped_steps_without_contacts\": " << r.skipped_steps << ",\n";
  os << "  \"wall_seconds\": " << json_number(r.wall_seconds) << ",\n";
  os << "  \"git\": \"" << json_escape(p.git) << "\",\n";
  os << "  \"build\": \"" << json_escape(p.build) << "\",\n";
  os << "  \"machine\": \"" << json_escape(p.machine) << "\",\n";
  os << "  \"date\": \"" << p.date_utc << "\"\n}\n";
  return os.str();
}

std::vector<std::string> write_report(const BenchResults& r, const std::string& dir_text) {
  namespace fs = std::filesystem;
  const fs::path dir(dir_text);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(dir_text + ": cannot create the output directory: " + ec.message());
  const Provenance prov = collect_provenance();
  const auto summary = summarise(r);
  std::vector<std::string> files;

  // Each file is written to a temporary and renamed; the large results.h5 first, so that on a
  // full disk its failure leaves both earlier files (a consistent pair) untouched.
  write_results_h5(r, prov, (dir / "results.h5").string());
  files.push_back((dir / "results.h5").string());
  write_text(dir / "summary.json", summary_json(r, summary, prov));
  files.push_back((dir / "summary.json").string());

  // Plots: python3 (Debian's, which has matplotlib and h5py) over results.h5.
  const std::vector<std::string> plots = {"convergence.png", "sweeps_per_step.png", "time_breakdown.png",
                                          "pareto.png"};
  for (const auto& p : plots) fs::remove(dir / p, ec);
  const std::string script = std::string(DC_SOURCE_DIR) + "/bench/plots/bench_plots.py";
  const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string cmd = py + " '" + script + "' '" + (dir / "results.h5").string() + "' '" + dir.string() + "'";
  const int rc = std::system(cmd.c_str());
  std::vector<std::string> missing;
  for (const auto& p : plots) {
    if (fs::exists(dir / p)) files.push_back((dir / p).string());
    else missing.push_back(p);
  }
  if (rc != 0 || !missing.empty())
    std::fprintf(stderr, "deepcontact bench: warning: plotting failed (exit %d); missing:%s\n", rc,
                 [&] { std::string m; for (auto& x : missing) m += " " + x; return m; }().c_str());

  std::ostringstream md;
  const int steps = r.starters.empty() ? 0 : static_cast<int>(r.starters[0].sweeps_to_tol.size());
  md << "# DeepContact warm-start benchmark\n\n";
  md << "Mode **" << (r.options.mode == Mode::Paired ? "paired" : "rollout") << "**, solver `" << r.options.solver
     << "`, " << r.options.sweeps << " sweeps, tolerance θ ≤ " << r.options.tolerance << " N, " << steps
     << " evaluated steps (" << r.skipped_steps << " steps without contacts skipped) over scene seeds";
  for (auto s : r.options.seeds) md << ' ' << s;
  md << ". Wall time " << fmt("%.1f", r.wall_seconds) << " s.\n\n";
  md << "Medians over steps. `*` marks oracle starters (they use this step's solution λ*; the oracle's cost is "
        "shown apart and is not included in total). `/zero` is the ratio to the zero warm start. "
        "`theses` gives the earlier theses' median iterations to 1e-4 N·s (Box2D impulses, r = 0.5; DESIGN §6).\n\n";
  md << format_table(r, summary, true) << "\n";
  md << "## Plots\n\n";
  const std::vector<std::pair<std::string, std::string>> captions = {
      {"convergence.png", "Convergence θ_k against sweep k: median and quartiles over steps (log scale)."},
      {"sweeps_per_step.png", "Sweeps until θ ≤ tol, per step of the trajectory."},
      {"time_breakdown.png", "Median time per step: warm start, PGS sweeps until tol, and the oracle (apart)."},
      {"pareto.png", "Speed/accuracy trade: residual, λ error, penetration and energy error against time per step "
                     "for sweep budgets 1…N."}};
  for (const auto& [file, cap] : captions) {
    if (fs::exists(dir / file)) md << "![" << file << "](" << file << ")\n\n" << cap << "\n\n";
    else md << "*(" << file << " missing: plotting failed — see stderr)*\n\n";
  }
  md << "## Reproducibility\n\n";
  md << "- git: `" << prov.git << "`\n- build: " << prov.build << "\n- machine: " << prov.machine
     << "\n- date: " << prov.date_utc << "\n- raw per-step figures: `results.h5` (layout in docs/bench.md)\n\n";
  md << "## Scene\n\n```toml\n" << scene_to_toml(r.options.scene) << "```\n";
  write_text(dir / "report.md", md.str());
  files.push_back((dir / "report.md").string());
  return files;
}

}  // namespace dc::bench
