#include "dc/bench/bench_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "bench_statistics_report.hpp"
#include "report_format.hpp"
#include "dc/bench/json_writer.hpp"
#include "dc/bench/quantiles.hpp"
#include "dc/bench/render_frame.hpp"
#include "dc/bench/solver_summary.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/io/atomic_file.hpp"
#include "report_plots.hpp"

namespace dc::bench {
namespace {

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

bool theses_apply(const WorldDef& scene) {
  WorldDef seed_scene;  // the defaults are the seed scene (docs/design.md §1)
  WorldDef d = scene;
  d.bodies.seed = seed_scene.bodies.seed;  // any seed and run length of that scene
  d.time.steps = seed_scene.time.steps;
  return d == seed_scene;
}

std::string format_table(const BenchResults& r, const std::vector<StarterSummary>& s, bool md) {
  const StarterSummary* zero = find(s, "zero");
  const int N = r.options.sweeps;
  std::vector<std::vector<std::string>> rows;
  const bool high = r.options.max_sweeps > 0;
  const std::string at_b = "resid@" + std::to_string(r.options.budget > 0 ? r.options.budget : std::min(100, N));
  const std::string at_n = "resid@" + std::to_string(N);
  const std::string hi_s = "sweeps cap " + std::to_string(r.options.max_sweeps), hi_n = "never cap " + std::to_string(r.options.max_sweeps);
  rows.push_back({"warm starter", "sweeps to tol (median)", "q1-q3", "/zero", "never", "warmstart ms",
                  "oracle ms", "solve ms", "total ms", "total /zero", "theses", at_b, at_n});
  if (high) rows.back().insert(rows.back().end(), {hi_s, hi_n});
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
                    thesis_reference(x.name), fmt("%.2e", x.residual_at_budget), fmt("%.2e", x.residual_at_cap)});
    if (high)
      rows.back().insert(rows.back().end(), {x.median_sweeps_high > r.options.max_sweeps ? "never" : fmt("%.0f", x.median_sweeps_high),
                                             fmt("%.1f%%", 100 * x.unconverged_share_high)});
  }
  if (!theses_apply(r.options.scene)) {  // the theses measured the seed scene only
    const auto col = static_cast<std::ptrdiff_t>(std::find(rows[0].begin(), rows[0].end(), "theses") - rows[0].begin());
    for (auto& row : rows) row.erase(row.begin() + col);
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

namespace {

/// One starter's object under "warmstarters". A sweep count above the run's sweeps means
/// "never reached the tolerance": null.
void starter_summary_json(JsonWriter& j, const BenchResults& r, const StarterSummary& x, const StarterSummary* zero) {
  const auto sweeps_or_null = [&](double v) { return v > r.options.sweeps ? std::nullopt : std::optional<double>(v); };
  const bool never = x.median_sweeps_to_tol > r.options.sweeps;
  j.key(x.name).begin_object();
  j.key("median_sweeps_to_tol").value(sweeps_or_null(x.median_sweeps_to_tol));
  j.key("q1_sweeps_to_tol").value(sweeps_or_null(x.sweeps_to_tol.q1));
  j.key("q3_sweeps_to_tol").value(sweeps_or_null(x.sweeps_to_tol.q3));
  j.key("unconverged_share").value(x.unconverged_share);
  j.key("warmstart_ms").value(x.warmstart_ms);
  j.key("oracle_ms").value(x.uses_oracle ? x.oracle_ms : 0.0);
  j.key("solve_ms").value(x.solve_ms);
  j.key("total_ms").value(x.total_ms);
  j.key("ns_per_row_sweep").value(x.ns_per_row_sweep);
  j.key("initial_error").value(x.initial_error);
  j.key("uses_oracle").value(x.uses_oracle);
  j.key("sweeps_ratio_to_zero");
  if (zero && zero->median_sweeps_to_tol > 0 && !never)
    j.value(x.median_sweeps_to_tol / zero->median_sweeps_to_tol);
  else
    j.null();
  j.key("total_ratio_to_zero");
  if (zero && zero->total_ms > 0)
    j.value(x.total_ms / zero->total_ms);
  else
    j.null();
  j.key("theses").value(theses_apply(r.options.scene) ? thesis_reference(x.name) : std::string());
  j.key("residual_at_budget").value(x.residual_at_budget);
  j.key("residual_at_cap").value(x.residual_at_cap);
  if (r.options.max_sweeps > 0) {
    j.key("median_sweeps_to_tol_high_cap");
    if (x.median_sweeps_high > r.options.max_sweeps) j.null(); else j.value(x.median_sweeps_high);
    j.key("unconverged_share_high_cap").value(x.unconverged_share_high);
  }
  j.end_object();
}

}  // namespace

std::string summary_json(const BenchResults& r, const std::vector<StarterSummary>& s, const Provenance& p,
                         const BenchStatistics* stats) {
  const StarterSummary* zero = find(s, "zero");
  JsonWriter j;
  j.begin_object(JsonWriter::Layout::Lines);
  j.key("warmstarters").begin_object(JsonWriter::Layout::Lines);
  for (const auto& x : s) starter_summary_json(j, r, x, zero);
  j.end_object();
  if (!r.pairs.empty()) {  // only with --solvers: a run without them has no "solvers" key
    j.key("solvers");
    solver_pairs_json(j, summarise_solver_pairs(r));
    j.key("accuracy").value(r.options.accuracy);
  }
  if (stats) {
    j.key("statistics");
    statistics_json(j, *stats);
  }
  j.key("family").value(r.options.family);
  j.key("budget").value(r.options.budget);
  j.key("max_sweeps").value(r.options.max_sweeps);
  j.key("warmup_steps").value(r.options.warmup_steps);
  j.key("oracle").value(r.options.oracle);
  j.key("jobs").value(r.options.jobs);
  j.key("scene").value(scene_to_toml(r.options.scene));
  j.key("seeds").begin_array();
  for (const std::uint64_t seed : r.options.seeds) j.value(seed);
  j.end_array();
  j.key("mode").value(r.options.mode == Mode::Paired ? "paired" : "rollout");
  j.key("solver").value(to_string(r.options.solver));
  j.key("sweeps").value(r.options.sweeps);
  j.key("tolerance").value(r.options.tolerance);
  j.key("evaluated_steps").value(r.starters.empty() ? std::size_t{0} : r.starters[0].sweeps_to_tol.size());
  j.key("skipped_steps_without_contacts").value(r.skipped_steps);
  // Median ms per evaluated step of the stages every starter shares (results.h5: /steps/*_ms).
  j.key("step_stage_ms").begin_object();
  j.key("collide").value(quartiles(r.collide_ms).median);
  j.key("assemble").value(quartiles(r.assemble_ms).median);
  j.key("integrate").value(quartiles(r.integrate_ms).median);
  j.end_object();
  j.key("wall_seconds").value(r.wall_seconds);
  j.key("git").value(p.git);
  j.key("build").value(p.build);
  j.key("machine").value(p.machine);
  j.key("date").value(p.date_utc);
  j.end_object();
  return j.str();
}

namespace {

/// report.md's opening: what ran (mode, solver, sweeps, tolerance, steps, seeds, wall time and
/// the shared stages), the run's particulars (warm-up, no oracle, higher cap) and how to read
/// the table.
std::string report_intro_markdown(const BenchResults& r) {
  std::ostringstream md;
  const int steps = r.starters.empty() ? 0 : static_cast<int>(r.starters[0].sweeps_to_tol.size());
  md << "# DeepContact warm-start benchmark: family `" << (r.options.family.empty() ? "seed" : r.options.family)
     << "`\n\n";
  md << "Mode **" << (r.options.mode == Mode::Paired ? "paired" : "rollout") << "**, solver `"
     << to_string(r.options.solver) << "`, " << r.options.sweeps << " sweeps, tolerance θ ≤ " << r.options.tolerance << " N, " << steps
     << " evaluated steps (" << r.skipped_steps << " steps without contacts skipped) over scene seeds";
  for (auto s : r.options.seeds) md << ' ' << s;
  md << ". Wall time " << fmt("%.1f", r.wall_seconds) << " s.";
  if (!r.collide_ms.empty())
    md << " Shared stages per step (medians): collide " << fmt("%.3f", quartiles(r.collide_ms).median)
       << " ms, assemble " << fmt("%.3f", quartiles(r.assemble_ms).median) << " ms, integrate "
       << fmt("%.3f", quartiles(r.integrate_ms).median) << " ms.";
  md << "\n\n";
  if (r.options.warmup_steps > 0)
    md << "The first " << r.options.warmup_steps << " steps of every seed were a warm-up (builtin + PGS to tol, not "
          "evaluated).\n\n";
  if (!r.options.oracle)
    md << "**Oracle skipped** (`--no-oracle`): the reference trajectory is advanced with builtin + PGS to tol/100 "
          "(cap " << std::max(r.options.sweeps, r.options.max_sweeps) << " sweeps); λ errors are against that λ, and "
          "no oracle starter ran.\n\n";
  md << "`resid@B` is the median natural-map residual [N] after B sweeps (B = the fixed budget `--budget`, and the cap)";
  if (r.options.max_sweeps > 0)
    md << "; `sweeps cap M` / `never cap M` are sweeps to tol and the unconverged share when a step may run up to "
          "M = `--max-sweeps` sweeps";
  md << ".\n\n";
  md << "Medians over steps. `*` marks oracle starters (they use this step's solution λ*; the oracle's cost is "
        "shown apart and is not included in total). `/zero` is the ratio to the zero warm start.\n\n";
  if (theses_apply(r.options.scene))
    md << "`theses` gives the earlier theses' median iterations to 1e-4 N·s on this (the seed) scene (Box2D "
          "impulses, r = 0.5; docs/design.md §6).\n\n";
  return md.str();
}

/// report.md's closing: where the run came from and its scene.
std::string report_provenance_markdown(const BenchResults& r, const Provenance& prov) {
  std::ostringstream md;
  md << "## Reproducibility\n\n";
  md << "- git: `" << prov.git << "`\n- build: " << prov.build << "\n- machine: " << prov.machine
     << "\n- date: " << prov.date_utc << "\n- raw per-step figures: `results.h5` (layout in docs/bench.md)\n\n";
  md << "## Scene\n\n```toml\n" << scene_to_toml(r.options.scene) << "```\n";
  return md.str();
}

/// IoError naming the plots the script did not make (report.md, already written, says so too).
void require_plots(const PlotRun& plots, const std::string& dir_text) {
  if (const auto missing = plots.missing(); !missing.empty()) {
    std::string m;
    for (const auto& x : missing) m += (m.empty() ? "" : ", ") + x;
    throw IoError(dir_text + "/report.md incomplete: missing " + m + " (plot script exit " +
                  std::to_string(plots.exit_code) + "; its output: " + plots.log + ")");
  }
}

}  // namespace

std::vector<std::string> write_report(const BenchResults& r, const std::string& dir_text) {
  namespace fs = std::filesystem;
  const fs::path dir(dir_text);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError(dir_text + ": cannot create the output directory: " + ec.message());
  const Provenance prov = collect_provenance();
  const auto summary = summarise(r);
  std::vector<std::string> files;

  const BenchStatistics stats = bench_statistics(r);
  // Each file is written to a temporary and renamed; the large results.h5 first, so that on a
  // full disk its failure leaves both earlier files (a consistent pair) untouched.
  write_results_h5(r, prov, (dir / "results.h5").string(), &stats);
  files.push_back((dir / "results.h5").string());
  write_text(dir / "summary.json", summary_json(r, summary, prov, &stats));
  files.push_back((dir / "summary.json").string());
  // The plots read results.h5; report.md embeds them, so it comes last.
  const PlotRun plots = make_report_plots(dir, !r.pairs.empty());
  for (const auto& p : plots.plots)
    if (p.state == PlotStatus::State::Written) files.push_back((dir / p.file).string());

  std::ostringstream md;
  md << report_intro_markdown(r);
  md << format_table(r, summary, true) << "\n";
  md << statistics_markdown(stats);
  md << solver_pairs_markdown(r, summarise_solver_pairs(r));
  md << plots_markdown(plots, r.options.mode);
  md << reference_frame_markdown(r, dir, files);
  md << report_provenance_markdown(r, prov);
  write_text(dir / "report.md", md.str());
  files.push_back((dir / "report.md").string());
  require_plots(plots, dir_text);
  return files;
}

}  // namespace dc::bench
