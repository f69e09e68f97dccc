#pragma once
// The plots of a bench report: bench/plots/bench_plots.py over DIR/results.h5, run with the
// Python of $DC_BENCH_PYTHON (default /usr/bin/python3, Debian's, with matplotlib and h5py).
// The script writes NAME.png, or NAME.na (one line: why the plot does not apply to this run)
// and exits non-zero if a plot failed; its output goes to DIR/plots.log.
#include <filesystem>
#include <string>
#include <vector>

#include "dc/bench/bench_results.hpp"

namespace dc::bench {

struct PlotStatus {
  enum class State { Written, NotApplicable, Missing };
  std::string file;   ///< e.g. "pareto.png"
  State state = State::Missing;
  std::string note;   ///< NotApplicable: the script's reason
};

struct PlotRun {
  std::vector<PlotStatus> plots;  ///< every plot of the report, in report order
  int exit_code = 0;              ///< of the plot script (128 + signal if killed, −1 if not started)
  std::string log;                ///< DIR/plots.log
  [[nodiscard]] std::vector<std::string> missing() const;
};

/// The plots of a report, in order; with `solvers` (a run with --solvers) also accuracy.png,
/// the solver comparison's median accuracy against time per step.
std::vector<std::string> report_plot_files(bool solvers = false);

/// Removes old plots (and .na notes) from `dir`, runs the script, collects what it made.
PlotRun make_report_plots(const std::filesystem::path& dir, bool solvers = false);

/// report.md's "Plots" section: each plot with its caption (per mode), a plot that does
/// not apply with its reason, a missing one with a pointer to plots.log.
std::string plots_markdown(const PlotRun& run, Mode mode);

}  // namespace dc::bench
