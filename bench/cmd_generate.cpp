// deepcontact generate: the CNN's training data set (issue 4; layout in docs/formats.md
// "Data set"). M simulations of a seed family, each step with contacts solved tightly and
// recorded as (feature image, label image, body state, contacts with λ*).
//
// Threads: simulations run in parallel on OpenMP worker threads (each one a pure function of
// its index, so the results do not depend on the thread count); ONE writer thread appends
// them to the file strictly in simulation order, so the file's datasets are identical for any
// --threads. Finished simulations wait in memory for their turn; a worker does not start a
// simulation more than 2·T ahead of the writer, which bounds that memory.
//
// Nothing lost: the file is OUT.partial until all M simulations are in, then renamed to OUT.
// Each simulation is committed by its /sims row (written last) and a flush, so a crash loses
// at most the simulations in flight; --resume continues from the last committed one.
// SIGINT sets a flag (the handler does nothing else); workers poll it between steps, the
// writer commits what is finished, and the command exits with status 130 and says how to resume.
#include <CLI/CLI.hpp>
#include <omp.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "cli_common.hpp"
#include "commands.hpp"
#include "sigint_guard.hpp"
#include "dc/engine/error.hpp"
#include "dc/learning/data_set.hpp"
#include "dc/warmstart/sph_warm_starter.hpp"
#include "progress_bar.hpp"

namespace dc::cli {
namespace {


struct GenerateArgs {
  SceneArgs scene;
  int sims = -1;
  std::uint64_t seed = 1;
  std::string count = "50..100";
  int steps = -1;
  int threads = 0;
  bool resume = false;
  bool force = false;
  bool log_completed = false;
  std::string out;
  std::string grid;
  std::string channels;
  std::string oracle = DataSetOracle{}.method;
  double oracle_tolerance = DataSetOracle{}.theta;
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
  std::tie(p.count_min, p.count_max) = parse_count(a.count);
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
  p.oracle.method = a.oracle;
  p.oracle.theta = a.oracle_tolerance;
  p.oracle.sweeps = a.oracle_sweeps;
  option("--oracle", [&] { p.oracle.validate(); });
  p.validate();
  return p;
}

void run(const GenerateArgs& a) {
  if (a.sims < 1) throw ConfigError("--sims must be >= 1 (got " + std::to_string(a.sims) + ")");
  if (a.out.empty()) throw ConfigError("--out is required");
  if (a.threads < 0) throw ConfigError("--threads must be >= 1");
  const DataSetParams params = make_params(a);
  const std::string partial = a.out + ".partial";
  namespace fs = std::filesystem;
  if (fs::exists(a.out) && !a.force) throw ConfigError(a.out + " exists; use --force to replace it");
  if (a.resume && !fs::exists(partial))
    throw ConfigError("--resume: " + partial + " does not exist (nothing to resume; run without --resume)");
  if (!a.resume && fs::exists(partial))
    throw ConfigError(partial + " exists (an interrupted run): add --resume to continue it, or delete it");

  const SimulationGenerator generator(params);
  DataSetWriter writer = a.resume ? DataSetWriter::resume(partial, params) : DataSetWriter::create(partial, params);
  const int first = writer.completed_simulations();
  const int threads = a.threads > 0 ? a.threads : std::max(1, omp_get_max_threads());
  const SigintGuard sigint;
  const auto t0 = std::chrono::steady_clock::now();

  std::mutex mutex;                    // guards ready, failure, written
  std::condition_variable changed;     // a simulation finished / was written / a worker quit
  std::map<int, SimulationRecord> ready;
  std::exception_ptr failure;
  int written = first;
  int workers_done = 0;                // workers that left their loop (guarded by mutex)
  std::atomic<int> next{first};
  std::atomic<bool> failed{false};
  const auto keep_going = [&] { return !interrupted() && !failed.load(std::memory_order_relaxed); };
  const int max_ahead = 2 * threads;
  long steps_done = 0;
  double worst_residual = 0;           // over the simulations written by this run [N]
  ProgressBar bar("generate", a.sims - first);

  const auto fail = [&](std::exception_ptr e) {
    std::lock_guard lock(mutex);
    if (!failure) failure = e;
    failed = true;
    changed.notify_all();
  };
  // Appends ready simulations in order; called by the writer thread only.
  const auto write_ready = [&](std::unique_lock<std::mutex>& lock) {
    for (auto it = ready.find(written); it != ready.end(); it = ready.find(written)) {
      SimulationRecord rec = std::move(it->second);
      ready.erase(it);
      lock.unlock();
      writer.append(rec);  // rows, /sims (seed last), flush
      if (a.log_completed) {
        std::fprintf(stderr, "completed %d samples %zu\n", rec.index, rec.samples());
        std::fflush(stderr);
      }
      bar.advance(1, "sim " + std::to_string(rec.index) + ": " + std::to_string(rec.bodies) + " bodies");
      lock.lock();
      ++written;
      steps_done += params.scene.time.steps;
      worst_residual = std::max(worst_residual, rec.max_residual);
      changed.notify_all();
    }
  };
  // One simulation on the calling thread; false when the loop should stop.
  const auto work_one = [&]() -> bool {
    const int i = next.fetch_add(1);
    if (i >= a.sims || !keep_going()) return false;
    {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return i < written + max_ahead || !keep_going(); });
    }
    std::optional<SimulationRecord> rec = generator.run(i, keep_going);
    if (!rec) return false;  // interrupted or another thread failed: drop the partial simulation
    std::lock_guard lock(mutex);
    ready.emplace(i, std::move(*rec));
    changed.notify_all();
    return true;
  };

  // T workers plus one writer thread (thread 0). If OpenMP grants a single thread, it
  // alternates: one simulation, then write it.
#pragma omp parallel num_threads(threads + 1)
  {
    const int id = omp_get_thread_num(), team = omp_get_num_threads();
    try {
      if (team == 1) {
        for (;;) {
          const bool more = work_one();
          std::unique_lock lock(mutex);
          write_ready(lock);
          if (!more) break;
        }
      } else if (id == 0) {
        std::unique_lock lock(mutex);
        for (;;) {
          write_ready(lock);
          if (written >= a.sims || failed) break;
          if (workers_done == team - 1 && ready.find(written) == ready.end()) break;
          changed.wait(lock);
        }
      } else {
        while (work_one()) {
        }
      }
    } catch (...) {
      fail(std::current_exception());
    }
    if (team > 1 && id != 0) {
      std::lock_guard lock(mutex);
      ++workers_done;
      changed.notify_all();
    }
  }
  bar.finish();
  if (failure) std::rethrow_exception(failure);
  const int done = writer.completed_simulations();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (done < a.sims) {
    writer.close();
    std::fprintf(stderr,
                 "deepcontact: interrupted: %d of %d simulations are saved in %s; run the same command with "
                 "--resume to continue\n",
                 done, a.sims, partial.c_str());
    exit_status() = 130;
    return;
  }
  const std::int64_t samples = writer.samples();
  writer.close();
  fs::rename(partial, a.out);
  const int fresh = done - first;
  std::printf(
      "Generated %d simulation%s (%d new, seeds %llu..%llu, %d..%d bodies, %d steps each) with %d thread%s in %.2f s "
      "(%.0f steps/s, %.2f s per simulation): %lld samples of %d feature channels on a %d x %d grid, lambda* by "
      "%s with worst natural-map residual %.3g N -> %s\n",
      done, done == 1 ? "" : "s", fresh, static_cast<unsigned long long>(params.seed),
      static_cast<unsigned long long>(params.seed + static_cast<std::uint64_t>(done) - 1), params.count_min,
      params.count_max, params.scene.time.steps, threads, threads == 1 ? "" : "s", wall,
      wall > 0 ? static_cast<double>(steps_done) / wall : 0.0, fresh > 0 ? wall / fresh : 0.0,
      static_cast<long long>(samples), static_cast<int>(params.image.channels.size()),
      sph_node_count(params.image.sph.grid.height, params.image.sph.grid.spacing),
      sph_node_count(params.image.sph.grid.width, params.image.sph.grid.spacing), params.oracle.describe().c_str(),
      worst_residual, a.out.c_str());
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
                  "Body count per simulation: N, or A..B drawn uniformly from Rng(S+i) (replaces [bodies] count)")
      ->capture_default_str();
  cmd->add_option("--steps", args->steps, "Steps per simulation (default: the scene's [time] steps)");
  cmd->add_option("--threads", args->threads, "Worker threads (default: OMP_NUM_THREADS or all cores)");
  cmd->add_option("--out", args->out, "Output HDF5 file (written as OUT.partial, renamed when complete)")->required();
  cmd->add_flag("--resume", args->resume, "Continue an interrupted run from OUT.partial (same parameters)");
  cmd->add_flag("--force", args->force, "Replace an existing OUT");
  cmd->add_option("--grid", args->grid,
                  "SPH grid KERNEL:D:H (default: the bench's sph setting, poly6:0.5:0.355 -> 61 x 61 on 30 x 30)");
  cmd->add_option("--channels", args->channels,
                  "Feature channels, comma-separated from mass,vx,vy,omega,contact_density,nx,ny,lambda_prev_n,"
                  "lambda_prev_t,vrel_n,vrel_t,gap "
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
