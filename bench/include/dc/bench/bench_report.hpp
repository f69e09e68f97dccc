#pragma once
// The bench report: the stdout table, summary.json, results.h5 (raw per-step figures),
// PNG plots (bench/plots/bench_plots.py) and report.md embedding them. Layouts: docs/bench.md.
// It only writes: what it writes comes from the results (bench_results.hpp), their summary
// (bench_summary.hpp) and their statistics (bench_statistics.hpp).
//
// Where the parts are: the table and summary.json in bench_report.cpp, results.h5 in
// bench_results_h5.cpp, the statistics' section / object / group in
// bench_statistics_report.cpp, the plots in report_plots.cpp, the reference frame in
// render_frame.cpp.
#include <string>
#include <vector>

#include "dc/bench/bench_results.hpp"
#include "dc/bench/bench_statistics.hpp"
#include "dc/bench/bench_summary.hpp"
#include "dc/bench/provenance.hpp"

namespace dc::bench {

/// The reference theses' median iterations to θ ≤ 1e-4 N·s (docs/design.md §6), or "" if none.
std::string thesis_reference(const std::string& starter);

/// True when the theses' figures apply: the seed scene (any seed, any number of steps). On
/// other scenes the table has no `theses` column and summary.json's "theses" is "".
bool theses_apply(const WorldDef& scene);

/// Plain-text table (also used in report.md as a Markdown table when `markdown`).
std::string format_table(const BenchResults& r, const std::vector<StarterSummary>& s, bool markdown);

/// `stats` (optional) becomes the "statistics" object (bench_statistics_report.hpp).
std::string summary_json(const BenchResults& r, const std::vector<StarterSummary>& s, const Provenance& p,
                         const BenchStatistics* stats = nullptr);

/// The HDF5 group of a starter under /warmstarters: its name with '%' → "%25" and '/' →
/// "%2F" (a model path in "cnn:models/x.h5" would otherwise nest groups). The exact name is
/// the group's `name` attribute; /warmstarter_groups lists the groups in table order.
std::string starter_group_name(const std::string& name);

/// Writes results.h5 atomically (tmp + rename); with `stats`, also its /statistics group.
void write_results_h5(const BenchResults& r, const Provenance& p, const std::string& path,
                      const BenchStatistics* stats = nullptr);

/// Writes everything into `dir` (created). Plots are made by bench/plots/bench_plots.py with
/// the Python of $DC_BENCH_PYTHON (default /usr/bin/python3, which has matplotlib and h5py);
/// its output goes to DIR/plots.log. A plot that does not apply to the run is named in
/// report.md with the reason. If a plot is missing, report.md says so and an IoError names
/// the missing files (the bench then exits non-zero). Returns the list of files written.
std::vector<std::string> write_report(const BenchResults& r, const std::string& dir);

}  // namespace dc::bench
