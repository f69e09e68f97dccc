#pragma once
// The one rule of `bench --out DIR` and Python's `bench(out=DIR)`: DIR may be new, empty, or an
// earlier bench output (every entry a name the bench writes, or a partial-run folder a killed
// run left); anything else is refused before the bench runs, naming the file in the way. The
// report is built in DIR/partial-run-PID-N and moved into DIR only when complete, so an
// interrupted or failed run leaves every earlier byte of DIR as it was (dc/io/output_path.hpp).
#include <string>
#include <vector>

#include "dc/bench/bench_results.hpp"
#include "dc/bench/scale_sweep.hpp"

namespace dc::bench {

/// True for a name the bench writes into its output directory: results.h5, summary.json,
/// report.md, the plots and their notes and logs, reference.h5 and its frame, and the size
/// sweep's scale.* files.
bool is_report_file(const std::string& name);

/// IoError with one line unless `dir` can take a bench report under the rule above (call it
/// before the bench runs).
void check_report_directory(const std::string& dir);

/// What to lock (dc::OutputLock) while writing `dir`: its absolute path without a trailing
/// slash, so that the lock file DIR.lock lies next to DIR also for "." and "DIR/".
std::string report_lock_target(const std::string& dir);

/// Writes the bench report (write_report) into `dir` under the rule above; returns the names
/// of the files written. A report whose plots could not be made is still this run's complete
/// report (report.md says what is missing): it is moved into `dir`, then the IoError naming
/// the missing plots is thrown.
std::vector<std::string> write_report_directory(const BenchResults& r, const std::string& dir);

/// The same for the size sweep's report (write_scale_report).
std::vector<std::string> write_scale_report_directory(const std::vector<ScalePoint>& points, ScaleAxis axis,
                                                      const std::string& dir);

}  // namespace dc::bench
