// deepcontact render run.h5 --out run.gif|run.mp4 [--every N] | --frame K --out frame.png:
// draw a trajectory (docs/python.md "deepcontact render"). Thin: the drawing is
// bench/plots/render_trajectory.py, run
// with the Python of $DC_BENCH_PYTHON (default /usr/bin/python3) like the report plots.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <system_error>
#include <string>
#include <vector>

#include "commands/commands.hpp"
#include "dc/bench/render_frame.hpp"
#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/output_path.hpp"

namespace dc::cli {
namespace {

struct RenderArgs {
  std::string file;
  std::string out;
  int frame = -1;
  int every = 0;
};

/// The renderer draws into OUT.tmp.EXT (the extension picks the format); only a complete
/// image is synced and renamed onto OUT, so a failed or killed render leaves OUT as it was.
std::string temporary_name(const std::string& out) {
  return out + ".tmp" + std::filesystem::path(out).extension().string();
}

void run(const RenderArgs& a) {
  check_output_file(a.out);
  const std::string tmp = temporary_name(a.out);
  std::vector<std::string> args{a.file, "--out", tmp, "--report-as", a.out};
  if (a.frame >= 0) args.insert(args.end(), {"--frame", std::to_string(a.frame)});
  if (a.every > 0) args.insert(args.end(), {"--every", std::to_string(a.every)});
  const int code = bench::run_renderer(args, "");
  if (code != 0) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
  }
  // 1: the script printed its one-line error itself; anything else means it could not run.
  if (code == 1) {
    exit_status() = 1;
    return;
  }
  if (code != 0)
    throw IoError("render: the renderer " + bench::renderer_command() + " failed (exit " + std::to_string(code) +
                  "; set DC_BENCH_PYTHON to a Python with numpy, h5py, matplotlib and Pillow)");
  try {
    sync_path(tmp);
    durable_rename(tmp, a.out);
  } catch (const IoError&) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand(
      "render",
      "Draw a trajectory (simulate --out run.h5): bodies, walls, contact forces (segments scaled and coloured by "
      "lambda_n) and time, as a GIF or MP4 (ffmpeg), or one frame as PNG");
  cmd->add_option("file", args->file, "Trajectory file (HDF5, docs/formats.md)")->required();
  cmd->add_option("--out", args->out, "run.gif, run.mp4, or with --frame an image (frame.png)")->required();
  cmd->add_option("--frame", args->frame, "Draw only state K (with the forces solved in step K) into --out")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--every", args->every,
                  "Animation: every N-th state (default: real time at 25 frames/s, e.g. 4 for dt = 0.01)")
      ->check(CLI::PositiveNumber);
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
