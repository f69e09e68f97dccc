#pragma once
// Running the trajectory renderer (bench/plots/render_trajectory.py) from C++: for
// `deepcontact render` and for the frame of the reference trajectory in the bench report.
#include <filesystem>
#include <string>
#include <vector>

#include "dc/bench/bench_results.hpp"

namespace dc::bench {

/// "'python' 'script'" as run (for messages).
std::string renderer_command();

/// Runs the renderer with `args` (its command line after the script). stdout/stderr are
/// inherited, or go to `log` when it is not empty (opened before the change of directory).
/// With `cwd` not empty the renderer runs there, so relative names in `args` are relative to
/// it (and what it prints names them so). Returns the exit status (128 + signal if killed, 127
/// if it could not be started).
int run_renderer(const std::vector<std::string>& args, const std::string& log, const std::string& cwd = "");

/// Paired bench: writes the reference trajectory of the first seed to DIR/reference.h5,
/// renders its last step with contacts to DIR/reference_frame.png (log: DIR/render.log) and
/// returns report.md's section embedding it (a note instead when rendering failed or the run
/// has no reference trajectory). `files` receives what was written.
std::string reference_frame_markdown(const BenchResults& r, const std::filesystem::path& dir,
                                     std::vector<std::string>& files);

}  // namespace dc::bench
