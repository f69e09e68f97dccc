// deepcontact simulate: run one scene and write its HDF5 trajectory (issue 2).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "dc/engine/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/io/trajectory_recorder.hpp"
#include "progress_bar.hpp"

namespace dc::cli {
namespace {

struct SimulateArgs {
  SceneArgs scene;
  int steps = -1;
  std::string out;
  std::string warmstart = "builtin";
  bool hash = false;  // print only the final state's hash
};

void run(const SimulateArgs& a) {
  WorldDef def = a.scene.load();
  if (a.steps >= 0) def.time.steps = a.steps;
  const auto t0 = std::chrono::steady_clock::now();
  World world(def);
  const auto solver = make_solver(def.solver.name);
  const SolverOptions opt = solver_options(def.solver);  // θ recorded
  const WarmStarterRegistry registry = full_warm_starter_registry();
  auto starter = registry.make(a.warmstart);

  TrajectoryRecorder rec(world);
  ProgressBar bar("simulate", def.time.steps);
  std::vector<int> sweeps;
  double max_pen = 0, worst_residual = 0;
  int nonconverged = 0, max_contacts = 0;
  const double e0 = world.kinetic_energy() + world.potential_energy();
  for (int s = 0; s < def.time.steps; ++s) {
    const StepReport r = world.step(*solver, opt, [&](const World& w) {
      return starter->initial_guess(StepView{w, nullptr});
    });
    starter->observe(StepView{world, nullptr}, r.solve.lambda);
    if (!r.solve.lambda.allFinite())
      throw std::runtime_error("step " + std::to_string(s + 1) + ": the solver returned a non-finite λ (" +
                               std::string(to_string(r.solve.status)) + ")");
    rec.record_step(world, r);
    if (r.rows > 0) {
      sweeps.push_back(r.solve.sweeps);
      worst_residual = std::max(worst_residual, r.solve.residual);
      if (def.solver.tolerance > 0 && r.solve.status != SolveStatus::Converged) ++nonconverged;
    }
    max_pen = std::max(max_pen, world.max_penetration());
    max_contacts = std::max(max_contacts, r.contacts);
    bar.advance();
  }
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
        "Simulated %zu circles for %d steps (%.3g s of simulated time, dt = %g s) in %.2f s wall: %zu contacts "
        "solved in all, at most %d in one step; solver '%s' with the '%s' warm start used a median of %d "
        "sweeps per step with contacts (max %d%s), worst natural-map residual %.3g N; max penetration %.3g m; "
        "total energy %.6g J -> %.6g J; final state hash %016llx.%s%s\n",
        world.bodies().size(), def.time.steps, def.time.steps * def.time.dt, def.time.dt, wall, rec.contacts(),
        max_contacts, def.solver.name.c_str(), a.warmstart.c_str(), sweeps.empty() ? 0 : sweeps[sweeps.size() / 2],
        sweeps.empty() ? 0 : sweeps.back(),
        def.solver.tolerance > 0 ? (", " + std::to_string(nonconverged) + " steps did not reach the tolerance").c_str() : "",
        worst_residual, max_pen, e0, e1, hash, a.out.empty() ? "" : " Trajectory: ", a.out.c_str());
  }
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
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
