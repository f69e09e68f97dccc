#include "report_plots.hpp"
#include "dc/core/install_paths.hpp"

#include <cstdlib>
#include <fstream>
#include <sys/wait.h>

namespace dc::bench {
namespace fs = std::filesystem;

std::vector<std::string> PlotRun::missing() const {
  std::vector<std::string> out;
  for (const auto& p : plots)
    if (p.state == PlotStatus::State::Missing) out.push_back(p.file);
  return out;
}

std::vector<std::string> report_plot_files(bool solvers) {
  std::vector<std::string> files = {"intervals.png", "convergence.png", "sweeps_per_step.png", "time_breakdown.png",
                                    "pareto.png"};
  if (solvers) files.emplace_back("accuracy.png");
  return files;
}

namespace {

/// "pareto.png" → "pareto.na".
std::string note_file(std::string png) {
  png.replace(png.rfind('.'), std::string::npos, ".na");
  return png;
}

std::string python_interpreter() {
  if (const char* py = std::getenv("DC_BENCH_PYTHON"); py && *py) return py;
  return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

std::string caption(const std::string& file, Mode mode) {
  const bool paired = mode == Mode::Paired;
  if (file == "intervals.png")
    return "Median sweeps to tol and median total time per step with their bootstrap 95 % intervals (bars) and the "
           "median of each seed (dots); see *Uncertainty*.";
  if (file == "convergence.png")
    return "Convergence θ_k against sweep k: median over steps, shaded quartiles when at most 6 starters ran "
           "(log scale).";
  if (file == "sweeps_per_step.png")
    return paired ? "Sweeps until θ ≤ tol along the reference trajectory (running median over 15 steps; seeds one "
                    "after another; never-converged steps count as sweeps + 1)."
                  : "Sweeps until θ ≤ tol along each starter's own trajectory (rollout: the steps are not paired "
                    "across starters; running median over 15 steps; never-converged steps count as sweeps + 1).";
  if (file == "time_breakdown.png")
    return paired ? "Median time per step: warm start, PGS sweeps until tol, and the shared oracle (apart)."
                  : "Median time per step: warm start, PGS sweeps until tol, and each oracle starter's own oracle "
                    "(apart).";
  if (file == "accuracy.png")
    return "Solver comparison: median accuracy (natural-map residual / heaviest weight) against time per step, warm "
           "start included, one curve per (solver, starter) pair; each step's trace ends when it reaches the target "
           "(dotted line) and then counts at it.";
  return "Speed/accuracy trade: residual, λ error, penetration and energy error against time per step for sweep "
         "budgets 1…N" + std::string(paired ? "." : " (each starter on its own trajectory, against its own λ*).");
}

}  // namespace

PlotRun make_report_plots(const fs::path& dir, bool solvers) {
  std::error_code ec;
  for (const auto& p : report_plot_files(true)) {
    fs::remove(dir / p, ec);
    fs::remove(dir / note_file(p), ec);
  }
  PlotRun run;
  run.log = (dir / "plots.log").string();
  const std::string script = data_path("bench/plots/bench_plots.py").string();
  std::string cmd;
  for (const std::string& word : {python_interpreter(), script, (dir / "results.h5").string(), dir.string()})
    cmd += "'" + word + "' ";
  cmd += ">'" + run.log + "' 2>&1";
  const int status = std::system(cmd.c_str());
  run.exit_code = status == -1 ? -1 : WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  for (const auto& p : report_plot_files(solvers)) {
    PlotStatus s;
    s.file = p;
    if (fs::exists(dir / p)) {
      s.state = PlotStatus::State::Written;
    } else if (std::ifstream na(dir / note_file(p)); na) {
      s.state = PlotStatus::State::NotApplicable;
      std::getline(na, s.note);
    }
    run.plots.push_back(s);
  }
  return run;
}

std::string plots_markdown(const PlotRun& run, Mode mode) {
  std::string md = "## Plots\n\n";
  for (const auto& p : run.plots) {
    switch (p.state) {
      case PlotStatus::State::Written:
        md += "![" + p.file + "](" + p.file + ")\n\n" + caption(p.file, mode) + "\n\n";
        break;
      case PlotStatus::State::NotApplicable:
        md += "*(" + p.file + " does not apply to this run: " + p.note + ")*\n\n";
        break;
      case PlotStatus::State::Missing:
        md += "*(" + p.file + " missing: the plot script failed — see plots.log)*\n\n";
        break;
    }
  }
  return md;
}

}  // namespace dc::bench
