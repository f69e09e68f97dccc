// deepcontact generate: the CNN's training data set (docs/design.md §4; layout in docs/formats.md
// "Data set"). M simulations of a seed family, each step with contacts solved tightly and
// recorded as (feature image, label image, body state, contacts with λ*).
//
// The pipeline (parallel simulations, one shard file each, the manifest, resume) is
// generate_data_set (dc/cnn/data_set_generation.hpp); this command parses the options,
// prints progress and the summary, and turns SIGINT/SIGTERM/SIGUSR1 into keep_going = false
// (exit status 130 / 143, one line with how to resume).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <memory>
#include <optional>

#include "cluster/comm.hpp"
#include "cluster/mpi_generate.hpp"
#include "cluster/sigint_guard.hpp"
#include "commands/cli_common.hpp"
#include "commands/commands.hpp"
#include "dc/bench/progress_bar.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/cnn/data_set_generation.hpp"
#include "dc/core/error.hpp"
#include "dc/io/output_path.hpp"
#include "dc/warmstart/sph_warm_starter.hpp"

namespace dc::cli {
namespace {


struct GenerateArgs {
  SceneArgs scene;
  int sims = -1;
  std::uint64_t seed = 1;
  std::string count;  // "" = the scene file's [bodies] count, or 50..100 for the seed scene
  int steps = -1;
  int threads = 0;
  bool resume = false;
  bool force = false;
  bool log_completed = false;
  std::string out;
  std::string grid;
  std::string channels;
  std::string oracle = to_string(DataSetOracle{}.method);
  double oracle_tolerance = DataSetOracle{}.tolerance;
  int oracle_sweeps = DataSetOracle{}.sweeps;
};

/// "N" or "A..B" with 0 ≤ A ≤ B.
std::pair<int, int> parse_count(const std::string& text) {
  const auto bad = [&] { return ConfigError("--count '" + text + "': expected N or A..B with 0 <= A <= B <= 1000000"); };
  const auto num = [&](const std::string& s) {
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 7) throw bad();
    return std::stoi(s);
  };
  const auto dots = text.find("..");
  const int a = num(dots == std::string::npos ? text : text.substr(0, dots));
  const int b = dots == std::string::npos ? a : num(text.substr(dots + 2));
  if (b < a || b > 1000000) throw bad();
  return {a, b};
}

DataSetParams make_params(const GenerateArgs& a) {
  DataSetParams p;
  p.scene = a.scene.load();
  if (a.steps >= 0) p.scene.time.steps = a.steps;
  if (p.scene.time.steps < 1) throw ConfigError("--steps: need at least 1 step per simulation");
  p.seed = a.seed;
  // A scene family keeps its own body count unless --count says otherwise.
  const std::string count =
      !a.count.empty() ? a.count : a.scene.file.empty() ? std::string("50..100") : std::to_string(p.scene.bodies.count);
  std::tie(p.count_min, p.count_max) = parse_count(count);
  p.image = FeatureImageDef::for_box(p.scene.world.width, p.scene.world.height);
  // Library errors get the option's name in front, so the one-line message says what to fix.
  const auto option = [](const char* name, const auto& parse) {
    try {
      parse();
    } catch (const std::exception& e) {
      throw ConfigError(std::string(name) + ": " + e.what());
    }
  };
  if (!a.grid.empty())
    option("--grid", [&] {
      parse_sph_setting(a.grid, p.image.sph);
      if (p.image.sph.normalisation != SphNormalisation::Shepard)
        throw ConfigError("labels are Shepard numerators; only the shepard normalisation is allowed");
    });
  if (!a.channels.empty()) option("--channels", [&] { p.image.channels = parse_feature_channels(a.channels); });
  option("--oracle", [&] {
    p.oracle.method = parse_oracle_kind(a.oracle);
    p.oracle.tolerance = a.oracle_tolerance;
    p.oracle.sweeps = a.oracle_sweeps;
    p.oracle.validate();
  });
  p.validate();
  return p;
}

/// The last lines of a finished run: what was generated, and where the time went.
void print_summary(const DataSetParams& params, const DataSetGenerationReport& r,
                   const Comm& comm) {
  const int fresh = r.completed - r.first;
  const double wall = r.wall_seconds;
  std::printf(
      "Generated %d simulation%s (%d new, seeds %llu..%llu, %d..%d bodies, %d steps each) with %s%d thread%s in %.2f s "
      "(%.0f steps/s, %.2f s per simulation): %lld samples of %d feature channels on a %d x %d grid, lambda* by "
      "%s with worst natural-map residual %.3g N -> %s\n",
      r.completed, r.completed == 1 ? "" : "s", fresh, static_cast<unsigned long long>(params.seed),
      static_cast<unsigned long long>(params.seed + static_cast<std::uint64_t>(r.completed) - 1), params.count_min,
      params.count_max, params.scene.time.steps,
      comm.parallel() ? (std::to_string(comm.size()) + " ranks x ").c_str() : "", r.threads,
      r.threads == 1 ? "" : "s", wall,
      wall > 0 ? static_cast<double>(r.steps) / wall : 0.0, fresh > 0 ? wall / fresh : 0.0,
      static_cast<long long>(r.samples), static_cast<int>(params.image.channels.size()),
      sph_node_count(params.image.sph.grid.height, params.image.sph.grid.spacing),
      sph_node_count(params.image.sph.grid.width, params.image.sph.grid.spacing), params.oracle.describe().c_str(),
      r.worst_residual, r.path.c_str());
  std::printf("generate: of the %.2f s, %s spent %.2f s (%.2f s CPU) writing shards; the manifest took "
              "%.2f s\n",
              wall, comm.parallel() ? "rank 0's workers" : "the workers", r.write_seconds, r.write_cpu_seconds, r.manifest_seconds);
}

void run(const GenerateArgs& a) {
  check_output_file(a.out);  // before any simulation
  check_output_extension("--out", a.out, kHdf5Extensions, "the HDF5 manifest of the data set");
  DataSetGenerationDef def;  // generate_data_set checks --sims, --out, --threads and the files
  def.params = make_params(a);
  def.out = a.out;
  def.simulations = a.sims;
  def.threads = a.threads;
  def.resume = a.resume;
  def.force = a.force;

  const SigintGuard stop_signals;
  std::optional<bench::ProgressBar> bar;
  DataSetGenerationHooks hooks;
  hooks.keep_going = [] { return !interrupted(); };
  const Comm& comm = world();  // across MPI ranks: each writes its own shards (mpi_generate.hpp)
  if (comm.is_root()) hooks.on_start = [&](int first, int) { bar.emplace("generate", a.sims - first); };
  hooks.on_committed = [&](const SimulationRecord& rec) {
    if (a.log_completed) {
      std::fprintf(stderr, "completed %d samples %zu\n", rec.index, rec.samples());
      std::fflush(stderr);
    }
    if (bar) bar->advance(1, "sim " + std::to_string(rec.index) + ": " + std::to_string(rec.bodies) + " bodies");
  };
  const DataSetGenerationReport r = generate_data_set(def, hooks, generate_partition(comm));
  if (bar) bar->finish();
  if (r.discarded > 0 && comm.is_root())
    std::fprintf(stderr, "deepcontact: generate: discarded %d incomplete shard%s (simulations being written when the "
                         "interrupted run stopped)\n", r.discarded, r.discarded == 1 ? "" : "s");
  if (!r.finished) {
    exit_status() = interrupted() ? interrupt_exit_status() : 130;  // 130: another rank was stopped
    if (comm.is_root())
      std::fprintf(stderr,
                   "deepcontact: interrupted%s%s: %d of %d simulations are saved in %s; run the same command with "
                   "--resume to continue\n",
                   interrupted() ? " by " : "", interrupt_signal_name(), r.completed, a.sims, r.path.c_str());
    return;
  }
  if (comm.is_root()) print_summary(def.params, r, comm);
}

}  // namespace

void add_generate_command(CLI::App& app) {
  auto args = std::make_shared<GenerateArgs>();
  auto* cmd = app.add_subcommand(
      "generate", "Generate the CNN data set: M seeded simulations, every step with contacts as (feature image, "
                  "label image, bodies, contacts with lambda*) in HDF5 (docs/formats.md 'Data set')");
  args->scene.add_options(*cmd);
  cmd->add_option("--sims", args->sims, "Number of simulations M (simulation i uses scene seed S+i)")->required();
  cmd->add_option("--seed", args->seed, "First scene seed S")->capture_default_str();
  cmd->add_option("--count", args->count,
                  "Body count per simulation: N, or A..B drawn uniformly from Rng(S+i) (replaces [bodies] count; "
                  "default: the --scene file's count, 50..100 without --scene)");
  cmd->add_option("--steps", args->steps, "Steps per simulation (default: the scene's [time] steps)");
  cmd->add_option("--threads", args->threads, "Worker threads (default: OMP_NUM_THREADS or all cores)");
  cmd->add_option("--out", args->out,
                  "Output data set: the manifest OUT (HDF5, written when all simulations are in) over the shards "
                  "in OUT.shards/ (one file per simulation, committed as it finishes)")
      ->required();
  cmd->add_flag("--resume", args->resume, "Continue the interrupted run named by OUT.partial (same parameters)");
  cmd->add_flag("--force", args->force, "Replace an existing OUT (once the new data set is complete)");
  cmd->add_option("--grid", args->grid,
                  "SPH grid KERNEL:D:H (default: the bench's sph setting, poly6:0.5:0.355 -> 61 x 61 on 30 x 30)");
  cmd->add_option("--channels", args->channels,
                  "Feature channels, comma-separated from mass,vx,vy,omega,contact_density,nx,ny,lambda_prev_n,"
                  "lambda_prev_t,vrel_n,vrel_t,gap,coverage,orient_c,orient_s,w_prev_n,w_prev_t "
                  "(default: mass,vx,vy,omega,contact_density)");
  cmd->add_option("--oracle", args->oracle,
                  "How lambda* is solved: pgs (matrix-free PGS from the builtin warm start until theta <= "
                  "tolerance or the sweep cap; ~7 ms/step on the seed scene) or newton (solve_oracle from the "
                  "builtin warm start; tighter, ~5x slower)")
      ->capture_default_str();
  cmd->add_option("--oracle-tolerance", args->oracle_tolerance,
                  "newton: accepted natural residual relative to max(1, |lambda|_inf); pgs: stopping theta [N]")
      ->capture_default_str();
  cmd->add_option("--oracle-sweeps", args->oracle_sweeps, "PGS sweep cap (pgs) / polish sweeps (newton)")
      ->capture_default_str();
  cmd->add_flag("--log-completed", args->log_completed,
                "Print 'completed I samples N' to stderr when simulation I is committed (for scripts and tests)");
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
