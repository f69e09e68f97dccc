// deepcontact simulate: run one scene and write its HDF5 trajectory (docs/formats.md).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <string>

#include "commands/cli_common.hpp"
#include "commands/commands.hpp"
#include "dc/bench/list_options.hpp"
#include "dc/bench/progress_bar.hpp"
#include "dc/bench/trajectory_recorder.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
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
};

/// CPU seconds of this process so far (all threads).
double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// One line "profile key=value …": steps, bodies, mean rows per step, mean wall-clock ms per
/// step of each stage (the columns of /solver/profile) and their total, and the CPU seconds
/// of the stepping loop (benchmarks/scripts/step-scaling.sh reads it).
void print_profile(const TrajectoryRecorder& rec, std::size_t bodies, long rows_sum, double cpu_s) {
  const int S = rec.steps(), W = TrajectoryRecorder::kProfileWidth;
  std::vector<double> mean(static_cast<std::size_t>(W), 0.0);
  for (int k = 0; k < S; ++k)
    for (int c = 0; c < W; ++c) mean[static_cast<std::size_t>(c)] += rec.profile()[static_cast<std::size_t>(k * W + c)];
  const double per_step_ms = S > 0 ? 1e3 / S : 0.0;
  for (double& m : mean) m *= per_step_ms;
  const double total = mean[0] + mean[1] + mean[2] + mean[3] + mean[4] + mean[5];  // broad phase ⊂ collide
  std::printf("profile steps=%d bodies=%zu rows=%.1f collide_ms=%.4f assemble_ms=%.4f warm_start_ms=%.4f "
              "solve_ms=%.4f integrate_ms=%.4f record_ms=%.4f broad_phase_ms=%.4f total_ms=%.4f cpu_s=%.3f\n",
              S, bodies, S > 0 ? static_cast<double>(rows_sum) / S : 0.0, mean[0], mean[1], mean[2], mean[3],
              mean[4], mean[5], mean[6], total, cpu_s);
}

void run(const SimulateArgs& a) {
  WorldDef def = a.scene.load();
  if (a.steps >= 0) def.time.steps = a.steps;
  const auto t0 = std::chrono::steady_clock::now();
  World world(def);
  const auto solver = make_solver(def.solver.name);
  const SolverOptions opt = solver_options(def.solver);  // θ recorded
  const WarmStarterRegistry registry = all_warm_starters(shipped_model());
  auto starter = registry.make(a.warmstart);

  TrajectoryRecorder rec(world);
  rec.reserve_steps(def.time.steps);
  bench::ProgressBar bar("simulate", def.time.steps);
  std::vector<int> sweeps;
  double max_pen = 0, worst_residual = 0;
  int nonconverged = 0, max_contacts = 0;
  const double e0 = world.kinetic_energy() + world.potential_energy();
  long rows_sum = 0;
  const double cpu0 = process_cpu_seconds();
  for (int s = 0; s < def.time.steps; ++s) {
    const StepReport r = world.step(*solver, opt, [&](const World& w) {
      return starter->initial_guess(StepView{w, nullptr});
    });
    starter->observe(StepView{world, nullptr}, r.solve.lambda);
    if (!r.solve.lambda.allFinite())
      throw std::runtime_error("step " + std::to_string(s + 1) + ": the solver returned a non-finite λ (" +
                               std::string(to_string(r.solve.status)) + ")");
    rec.record_step(world, r);
    rows_sum += r.rows;
    if (r.rows > 0) {
      sweeps.push_back(r.solve.sweeps);
      worst_residual = std::max(worst_residual, r.solve.residual);
      if (def.solver.tolerance > 0 && r.solve.status != SolveStatus::Converged) ++nonconverged;
    }
    max_pen = std::max(max_pen, world.max_penetration());
    max_contacts = std::max(max_contacts, r.contacts);
    bar.advance();
  }
  const double cpu_s = process_cpu_seconds() - cpu0;
  bar.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::sort(sweeps.begin(), sweeps.end());
  const double e1 = world.kinetic_energy() + world.potential_energy();
  // FNV-1a over the bit patterns of the final positions, angles, velocities and ω: equal on
  // every build and x86-64 CPU for the same scene (docs/reproducibility.md).
  const auto hash = static_cast<unsigned long long>(state_hash(world.bodies()));
  if (a.hash) {
    std::printf("%016llx\n", hash);
  } else {
    std::printf(
        "Simulated %s for %d steps (%.3g s of simulated time, dt = %g s) in %.2f s wall: %zu contacts "
        "solved in all, at most %d in one step; solver '%s' with the '%s' warm start used a median of %d "
        "sweeps per step with contacts (max %d%s), worst natural-map residual %.3g N; max penetration %.3g m; "
        "total energy %.6g J -> %.6g J; final state hash %016llx.%s%s\n",
        describe_bodies(world.bodies()).c_str(), def.time.steps, def.time.steps * def.time.dt, def.time.dt, wall, rec.contacts(),
        max_contacts, def.solver.name.c_str(), a.warmstart.c_str(), sweeps.empty() ? 0 : sweeps[sweeps.size() / 2],
        sweeps.empty() ? 0 : sweeps.back(),
        def.solver.tolerance > 0 ? (", " + std::to_string(nonconverged) + " steps did not reach the tolerance").c_str() : "",
        worst_residual, max_pen, e0, e1, hash, a.out.empty() ? "" : " Trajectory: ", a.out.c_str());
  }
  if (a.profile) print_profile(rec, world.bodies().size(), rows_sum, cpu_s);
  if (!a.out.empty()) rec.write(a.out, scene_to_toml(def), a.warmstart);
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  auto* cmd = app.add_subcommand("simulate", "Simulate a scene and write its trajectory (HDF5, docs/formats.md)");
  args->scene.add_options(*cmd);
  cmd->add_option("--steps", args->steps, "Number of steps (default: the scene's [time] steps)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--out", args->out, "Write the trajectory to this HDF5 file (atomically)");
  cmd->add_option("--warmstart", args->warmstart, "Warm starter used by the solver (see `bench --list`)")
      ->capture_default_str();
  cmd->add_flag("--hash", args->hash,
                "Print only the final state's hash (16 hex digits; equal on every build, docs/reproducibility.md)");
  cmd->add_flag("--profile", args->profile,
                "Also print one line 'profile key=value ...': mean wall-clock ms per step of each stage "
                "(collide, assemble, warm start, solve, integrate, record; /solver/profile) and the loop's CPU s");
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
