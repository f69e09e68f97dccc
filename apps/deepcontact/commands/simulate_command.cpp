// deepcontact simulate: run one scene and stream its HDF5 trajectory to disk (docs/formats.md;
// TrajectoryWriter: memory independent of the step count, OUT appears complete or not at all).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <optional>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "cluster/sigint_guard.hpp"
#include "commands/cli_common.hpp"
#include "commands/commands.hpp"
#include "dc/bench/list_options.hpp"
#include "dc/lcp/problem_export.hpp"
#include "dc/bench/progress_bar.hpp"
#include "dc/engine/trajectory_recorder.hpp"
#include "dc/engine/trajectory_writer.hpp"
#include "dc/io/output_lock.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/io/output_path.hpp"
#include "dc/research/research_starters.hpp"

namespace dc::cli {
namespace {

/// "100 circles", "60 polygons", "66 bodies (6 circles, 60 polygons)": the bodies by shape
/// (boxes are polygons in the engine's shape table).
std::string describe_bodies(const BodyState& bodies) {
  if (bodies.shapes.empty()) return std::to_string(bodies.size()) + (bodies.size() == 1 ? " circle" : " circles");
  std::map<std::string, std::size_t> count;
  for (const ShapeKind k : bodies.shapes.kind) ++count[shape_kind_name(k)];
  const auto phrase = [](const std::string& kind, std::size_t n) { return std::to_string(n) + " " + kind + (n == 1 ? "" : "s"); };
  if (count.size() == 1) return phrase(count.begin()->first, count.begin()->second);
  std::string parts;
  for (const auto& [kind, n] : count) parts += (parts.empty() ? "" : ", ") + phrase(kind, n);
  return std::to_string(bodies.size()) + " bodies (" + parts + ")";
}

struct SimulateArgs {
  SceneArgs scene;
  int steps = -1;
  std::string out;
  std::string warmstart = "builtin";
  bool hash = false;  // print only the final state's hash
  bool profile = false;  // also print the mean per-stage step profile (one "profile" line)
  std::string export_dir;       // --export-problems DIR ("" = none)
  int export_every = 1;         // --every K
  std::string export_format = "fclib";  // --format fclib|siconos-fc
};

/// CPU seconds of this process so far (all threads).
double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Sums over the steps of the per-stage seconds (the columns of /solver/profile).
using ProfileSums = std::array<double, TrajectoryRecorder::kProfileWidth>;

/// One line "profile key=value …": steps, bodies, mean rows per step, mean wall-clock ms per
/// step of each stage (the columns of /solver/profile) and their total, and the CPU seconds
/// of the stepping loop (benchmarks/scripts/step-scaling.sh reads it).
void print_profile(const ProfileSums& sum, int S, std::size_t bodies, long rows_sum, double cpu_s) {
  ProfileSums mean{};
  const double per_step_ms = S > 0 ? 1e3 / S : 0.0;
  for (std::size_t c = 0; c < mean.size(); ++c) mean[c] = sum[c] * per_step_ms;
  const double total = mean[0] + mean[1] + mean[2] + mean[3] + mean[4] + mean[5];  // broad phase ⊂ collide
  std::printf("profile steps=%d bodies=%zu rows=%.1f collide_ms=%.4f assemble_ms=%.4f warm_start_ms=%.4f "
              "solve_ms=%.4f integrate_ms=%.4f record_ms=%.4f broad_phase_ms=%.4f total_ms=%.4f cpu_s=%.3f\n",
              S, bodies, S > 0 ? static_cast<double>(rows_sum) / S : 0.0, mean[0], mean[1], mean[2], mean[3],
              mean[4], mean[5], mean[6], total, cpu_s);
}

/// What the stepping loop measured, for the summary line.
struct RunFigures {
  int steps = 0;  ///< steps done (fewer than asked when stopped by a signal)
  std::vector<int> sweeps;
  double max_pen = 0, worst_residual = 0;
  int nonconverged = 0, max_contacts = 0;
  long rows_sum = 0;
  std::int64_t contacts = 0;
  ProfileSums profile{};
  double cpu_s = 0;
};

/// Steps the world up to `steps` times (stopping early at a stop signal), streaming every
/// step to `out` when there is one: nothing of the trajectory is kept in memory.
RunFigures step_world(World& world, const WorldDef& def, WarmStarter& starter, TrajectoryWriter* out,
                      ProblemExporter* exporter) {
  const auto solver = make_solver(def.solver.name);
  const SolverOptions opt = solver_options(def.solver);  // θ recorded
  bench::ProgressBar bar("simulate", def.time.steps);
  RunFigures f;
  const double cpu0 = process_cpu_seconds();
  double record_s = 0;
  const bool engine_builtin = is_builtin_warm_starter(starter);
  for (int s = 0; s < def.time.steps && !interrupted(); ++s) {
    Eigen::VectorXd guess;  // this step's λ⁰, for an exported problem's /guesses
    const bool exported = exporter && exporter->due(s + 1);
    // builtin: the engine's own copy of it (the same λ⁰; with an internal body order it runs
    // in the internal rows), unless the exported problem needs λ⁰ itself.
    const StepReport r = engine_builtin && !exported
                             ? world.step(*solver, opt, World::WarmStart::PreviousLambda)
                             : world.step(*solver, opt, [&](const World& w) {
                                 guess = starter.initial_guess(StepView{w, nullptr});
                                 return guess;
                               });
    if (exported) exporter->write(s + 1, world.problem(), r.solve.lambda, guess);
    starter.observe(StepView{world, nullptr}, r.solve.lambda);
    if (!r.solve.lambda.allFinite())
      throw std::runtime_error("step " + std::to_string(s + 1) + ": the solver returned a non-finite λ (" +
                               std::string(to_string(r.solve.status)) + ")");
    const auto t0 = std::chrono::steady_clock::now();
    if (out) out->record_step(world, r, record_s);
    record_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const StepProfile& p = r.profile;
    const ProfileSums step{1e-3 * p.collide_ms, 1e-3 * p.assemble_ms, 1e-3 * p.warmstart_ms, 1e-3 * p.solve_ms,
                           1e-3 * p.integrate_ms, record_s, 1e-3 * p.broad_phase_ms};
    for (std::size_t c = 0; c < step.size(); ++c) f.profile[c] += step[c];
    f.rows_sum += r.rows;
    f.contacts += r.contacts;
    if (r.rows > 0) {
      f.sweeps.push_back(r.solve.sweeps);
      f.worst_residual = std::max(f.worst_residual, r.solve.residual);
      if (def.solver.tolerance > 0 && !stopped_at_tolerance(r.solve.status)) ++f.nonconverged;
    }
    f.max_pen = std::max(f.max_pen, world.max_penetration());
    f.max_contacts = std::max(f.max_contacts, r.contacts);
    ++f.steps;
    bar.advance();
  }
  f.cpu_s = process_cpu_seconds() - cpu0;
  bar.finish();
  return f;
}

/// Where an interrupted run's steps go: OUT with ".interrupted" before its extension
/// (run.h5 → run.interrupted.h5), so that a complete OUT of an earlier run stays as it was.
std::string interrupted_name(const std::string& out) {
  const std::filesystem::path p(out);
  return (p.parent_path() / (p.stem().string() + ".interrupted" + p.extension().string())).string();
}

void run(const SimulateArgs& a) {
  if (!a.out.empty()) {  // before any work: a bad --out costs nothing
    check_output_file(a.out);
    check_output_extension("--out", a.out, kHdf5Extensions, "an HDF5 trajectory");
  }
  std::optional<ProblemExporter> exporter;  // creates and checks the folder before the run
  if (!a.export_dir.empty())
    exporter.emplace(ProblemExportDef{a.export_dir, a.export_every, parse_problem_format(a.export_format)});
  WorldDef def = a.scene.load();
  if (a.steps >= 0) def.time.steps = a.steps;
  const auto t0 = std::chrono::steady_clock::now();
  World world(def);
  const WarmStarterRegistry registry = all_warm_starters(shipped_model());
  auto starter = registry.make(a.warmstart);
  std::optional<OutputLock> lock;
  std::optional<TrajectoryWriter> out;
  if (!a.out.empty()) {
    lock.emplace(a.out);
    out.emplace(a.out, world, scene_to_toml(def), a.warmstart);
  }
  const SigintGuard stop_signals;
  const double e0 = world.kinetic_energy() + world.potential_energy();
  RunFigures f = step_world(world, def, *starter, out ? &*out : nullptr, exporter ? &*exporter : nullptr);
  if (interrupted()) {
    const std::string partial = a.out.empty() ? "" : interrupted_name(a.out);
    if (out) out->commit(partial);
    std::fprintf(stderr, "deepcontact: interrupted by %s after %d of %d steps%s%s%s\n", interrupt_signal_name(), f.steps,
                 def.time.steps, out ? "; the trajectory of those steps is in " : " (nothing written)", partial.c_str(),
                 out ? (" (" + a.out + " is as it was)").c_str() : "");
    exit_status() = interrupt_exit_status();
    return;
  }
  if (out) out->commit();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::sort(f.sweeps.begin(), f.sweeps.end());
  const double e1 = world.kinetic_energy() + world.potential_energy();
  // FNV-1a over the bit patterns of the final positions, angles, velocities and ω: equal on
  // every build and x86-64 CPU for the same scene (docs/reproducibility.md).
  const auto hash = static_cast<unsigned long long>(state_hash(world.bodies()));
  if (a.hash) {
    std::printf("%016llx\n", hash);
  } else {
    std::printf(
        "Simulated %s for %d steps (%.3g s of simulated time, dt = %g s) in %.2f s wall: %lld contacts "
        "solved in all, at most %d in one step; solver '%s' with the '%s' warm start used a median of %d "
        "sweeps per step with contacts (max %d%s), worst natural-map residual %.3g N; max penetration %.3g m; "
        "total energy %.6g J -> %.6g J; final state hash %016llx.%s%s\n",
        describe_bodies(world.bodies()).c_str(), def.time.steps, def.time.steps * def.time.dt, def.time.dt, wall,
        static_cast<long long>(f.contacts), f.max_contacts, to_string(def.solver.name).c_str(), a.warmstart.c_str(),
        f.sweeps.empty() ? 0 : f.sweeps[f.sweeps.size() / 2], f.sweeps.empty() ? 0 : f.sweeps.back(),
        def.solver.tolerance > 0 ? (", " + std::to_string(f.nonconverged) + " steps did not reach the tolerance").c_str() : "",
        f.worst_residual, f.max_pen, e0, e1, hash, a.out.empty() ? "" : " Trajectory: ", a.out.c_str());
  }
  if (a.profile) print_profile(f.profile, f.steps, world.bodies().size(), f.rows_sum, f.cpu_s);
  if (exporter && !a.hash) std::printf("Exported %d problems to %s\n", exporter->written(), a.export_dir.c_str());
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  auto* cmd = app.add_subcommand("simulate", "Simulate a scene and write its trajectory (HDF5, docs/formats.md)");
  args->scene.add_options(*cmd);
  cmd->add_option("--steps", args->steps, "Number of steps (default: the scene's [time] steps)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--out", args->out,
                  "Write the trajectory to this HDF5 file (streamed to OUT.tmp, renamed when complete; SIGINT/"
                  "SIGTERM/SIGUSR1 stop at the next step and keep the steps done in OUT-STEM.interrupted.h5, "
                  "leaving OUT as it was)");
  cmd->add_option("--warmstart", args->warmstart, "Warm starter used by the solver (see `bench --list`)")
      ->capture_default_str();
  cmd->add_flag("--hash", args->hash,
                "Print only the final state's hash (16 hex digits; equal on every build, docs/reproducibility.md)");
  cmd->add_flag("--profile", args->profile,
                "Also print one line 'profile key=value ...': mean wall-clock ms per step of each stage "
                "(collide, assemble, warm start, solve, integrate, record; /solver/profile) and the loop's CPU s");
  cmd->add_option("--export-problems", args->export_dir,
                  "Write each exported step's frictional-contact problem to this folder (FCLIB with the solver's "
                  "lambda as /solution and the warm start as /guesses/1, or Siconos .dat; docs/lcp.md)");
  cmd->add_option("--every", args->export_every, "--export-problems: export every K-th step")
      ->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--format", args->export_format, "--export-problems: fclib (.hdf5) or siconos-fc (.dat)")
      ->check(CLI::IsMember({"fclib", "siconos-fc"}))->capture_default_str();
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
