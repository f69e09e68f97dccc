// `deepcontact stress [--out DIR] [--quick] [--only TEXT]` (docs/robustness.md): runs the extreme
// scenes of stress_scenarios.cpp — mass ratios, Δt, tall columns, many bodies, radius
// scales, friction, degenerate contacts, momentum — and tabulates per scenario what held and
// where the engine reached a limit. The table goes to stdout and, written atomically (a
// temporary name renamed into place), to DIR/stress.md and DIR/stress.csv.
// Limits reached are results, not errors: the exit status is 0 unless the command itself
// fails (bad option, unwritable directory).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands/commands.hpp"
#include "dc/bench/stress_scenarios.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/world.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/output_path.hpp"

namespace dc::cli {
namespace {

struct StressArgs {
  std::string out = "results-stress";
  bool quick = false;
  std::string only;
};

std::string num(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string pct(int part, int whole) { return whole > 0 ? num("%.0f%%", 100.0 * part / whole) : "-"; }

struct Row {
  const stress::Scenario* scenario;
  stress::RunStats stats;
  std::string verdict;
  std::size_t bodies = 0;
};

/// One column of the table: header and the cell text of a row.
struct Column {
  const char* header;
  std::string (*cell)(const Row&);
};

const std::vector<Column>& columns() {
  static const std::vector<Column> cols = {
      {"family", [](const Row& r) { return r.scenario->family; }},
      {"scenario", [](const Row& r) { return r.scenario->params; }},
      {"bodies", [](const Row& r) { return std::to_string(r.bodies); }},
      {"dt", [](const Row& r) { return num("%g", r.scenario->def.time.dt); }},
      {"mu", [](const Row& r) { return num("%g", r.scenario->def.contact.friction); }},
      {"sweeps", [](const Row& r) { return std::to_string(r.scenario->def.solver.sweeps); }},
      {"tol", [](const Row& r) { return num("%g", r.scenario->def.solver.tolerance); }},
      {"steps", [](const Row& r) { return std::to_string(r.stats.steps); }},
      {"wall_s", [](const Row& r) { return num("%.2f", r.stats.wall_s); }},
      {"collide_ms",  // min of repeated calls where measured (many bodies), else the mean per step
       [](const Row& r) {
         return num("%.3g", r.stats.collide_min_ms > 0 ? r.stats.collide_min_ms
                            : r.stats.steps            ? r.stats.collide_ms / r.stats.steps
                                                       : 0.0);
       }},
      {"max_pen_m", [](const Row& r) { return num("%.3g", r.stats.max_penetration); }},
      {"rest_pen_m", [](const Row& r) { return num("%.3g", r.stats.rest_penetration); }},
      {"slop_m", [](const Row& r) { return num("%.3g", r.scenario->def.contact.slop); }},
      {"energy_growth_J", [](const Row& r) { return num("%.3g", r.stats.max_energy_growth); }},
      {"energy_bound_J",
       [](const Row& r) { return r.scenario->energy_tol >= 1e299 ? std::string("-") : num("%.3g", r.scenario->energy_tol); }},
      {"momentum_drift_rel",
       [](const Row& r) {
         // Only meaningful without walls and gravity (the momentum rows).
         return r.scenario->check_momentum && r.stats.momentum_scale > 0
                    ? num("%.2g", r.stats.momentum_drift / r.stats.momentum_scale)
                    : std::string("-");
       }},
      {"nan", [](const Row& r) { return std::string(r.stats.nonfinite ? "yes" : "no"); }},
      {"converged", [](const Row& r) { return pct(r.stats.converged, r.stats.solves); }},
      {"tolerance_reached", [](const Row& r) { return pct(r.stats.tolerance_reached, r.stats.solves); }},
      {"sweep_limit", [](const Row& r) { return pct(r.stats.sweep_limit, r.stats.solves); }},
      {"diverged", [](const Row& r) { return pct(r.stats.diverged, r.stats.solves); }},
      {"failed", [](const Row& r) { return pct(r.stats.failed + r.stats.invalid + r.stats.infeasible, r.stats.solves); }},
      {"median_sweeps", [](const Row& r) { return num("%g", r.stats.median_sweeps); }},
      {"max_residual_N", [](const Row& r) { return num("%.3g", r.stats.max_residual); }},
      {"verdict", [](const Row& r) { return r.verdict; }},
  };
  return cols;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string to_csv(const std::vector<Row>& rows) {
  std::ostringstream os;
  const auto& cols = columns();
  for (std::size_t c = 0; c < cols.size(); ++c) os << (c ? "," : "") << cols[c].header;
  os << "\n";
  for (const Row& r : rows) {
    for (std::size_t c = 0; c < cols.size(); ++c) os << (c ? "," : "") << csv_field(cols[c].cell(r));
    os << "\n";
  }
  return os.str();
}

std::string to_markdown(const std::vector<Row>& rows, bool quick, double total_s) {
  std::ostringstream os;
  const auto& cols = columns();
  os << "# deepcontact stress" << (quick ? " --quick" : "") << "\n\n"
     << "Extreme scenes of docs/robustness.md; " << rows.size() << " scenarios in " << num("%.1f", total_s)
     << " s. `rest_pen_m` is the worst overlap over the last steps of the run (the at-rest window); "
        "energy growth is max_t (E_t - min_{s<=t} E_s); momentum drift is relative to the initial sum m|v| "
        "(rows without walls and gravity only); solver shares are over the steps with contacts.\n\n|";
  for (const Column& c : cols) os << " " << c.header << " |";
  os << "\n|";
  for (std::size_t c = 0; c < cols.size(); ++c) os << "---|";
  os << "\n";
  for (const Row& r : rows) {
    os << "|";
    for (const Column& c : cols) {
      std::string cell = c.cell(r);
      for (char& ch : cell)
        if (ch == '|') ch = '/';
      os << " " << cell << " |";
    }
    os << "\n";
  }
  return os.str();
}

void write_atomically(const std::filesystem::path& path, const std::string& text) {
  write_file_atomically(path.string(), text);
}

void run(const StressArgs& a) {
  const std::vector<stress::Scenario> scenarios = stress::stress_scenarios(a.quick);
  std::vector<Row> rows;
  rows.reserve(scenarios.size());
  std::error_code ec;
  if (!a.out.empty()) {
    check_output_directory(a.out);  // one line naming the cause, before the scenarios run
    std::filesystem::create_directories(a.out, ec);
    if (ec) throw IoError(a.out + ": cannot create the output directory: " + ec.message());
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<int> index_of(scenarios.size(), -1);  // scenario index → row index
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    const stress::Scenario& s = scenarios[i];
    if (!a.only.empty() && (s.family + " " + s.params).find(a.only) == std::string::npos) continue;
    World world = s.state ? World(s.def, *s.state) : World(s.def);
    const auto solver = make_solver(s.def.solver.name);
    Row row{&s, stress::run_world(world, *solver, stress::solver_options(s.def), s.run), "", world.bodies().size()};
    const Row* ref = s.linear_ref >= 0 && index_of[static_cast<size_t>(s.linear_ref)] >= 0
                         ? &rows[static_cast<size_t>(index_of[static_cast<size_t>(s.linear_ref)])]
                         : nullptr;
    row.verdict = stress::verdict(s, row.stats, ref ? ref->scenario : nullptr, ref ? &ref->stats : nullptr);
    std::fprintf(stderr, "[%zu/%zu] %s: %s (%.2f s) %s\n", i + 1, scenarios.size(), s.family.c_str(),
                 s.params.c_str(), row.stats.wall_s, row.verdict.c_str());
    index_of[i] = static_cast<int>(rows.size());
    rows.push_back(std::move(row));
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string md = to_markdown(rows, a.quick, total);
  std::fputs(md.c_str(), stdout);
  std::fflush(stdout);
  if (!a.out.empty()) {
    write_atomically(std::filesystem::path(a.out) / "stress.md", md);
    write_atomically(std::filesystem::path(a.out) / "stress.csv", to_csv(rows));
    std::fprintf(stderr, "stress: wrote %s/stress.md and %s/stress.csv\n", a.out.c_str(), a.out.c_str());
  }
}

}  // namespace

void add_stress_command(CLI::App& app) {
  auto args = std::make_shared<StressArgs>();
  auto* cmd = app.add_subcommand(
      "stress",
      "Run the extreme scenes (mass ratios to 1e6, dt 1e-4..0.05, tall columns, 10^4+ bodies, radius scale "
      "1e-3..1e2, friction 0..10, touching/coincident/corner/empty scenes) and tabulate penetration, energy "
      "growth, momentum drift, NaN, solver statuses and a verdict per scene (docs/robustness.md)");
  cmd->add_option("--out", args->out, "Directory for stress.md and stress.csv (\"\" = stdout only)")
      ->capture_default_str();
  cmd->add_flag("--quick", args->quick, "A reduced set of scenes (seconds instead of minutes)");
  cmd->add_option("--only", args->only, "Run only the scenarios whose 'family params' text contains TEXT");
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
