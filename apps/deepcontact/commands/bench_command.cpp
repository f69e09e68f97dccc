// deepcontact bench: compare warm starters on the same scenes (docs/design.md §6, docs/bench.md).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "cluster/comm.hpp"
#include "cluster/mpi_bench.hpp"
#include "cluster/sigint_guard.hpp"
#include "commands/cli_common.hpp"
#include "commands/commands.hpp"
#include "dc/bench/bench_report.hpp"
#include "dc/bench/bench_runner.hpp"
#include "dc/bench/bench_summary.hpp"
#include "dc/bench/list_options.hpp"
#include "dc/bench/progress_bar.hpp"
#include "dc/bench/report_directory.hpp"
#include "dc/bench/scale_sweep.hpp"
#include "dc/core/error.hpp"
#include "dc/io/output_lock.hpp"
#include "dc/research/research_starters.hpp"
#include <filesystem>

namespace dc::cli {
namespace {

struct BenchArgs {
  SceneArgs scene;
  std::string warmstarts;
  std::string seeds = "1..8";  // enough for zero vs builtin and cnn to separate, ~5 min on 2 idle cores (docs/bench.md)
  int sweeps = 0;
  double tol = 1e-2;
  std::string mode = "paired";
  std::string out;
  std::string solver = "pgs-colored";
  std::string model;
  int steps = 0;
  bool quick = false;
  bool list = false;
  int max_sweeps = 0;
  int budget = 0;
  int warmup_steps = 0;
  bool no_oracle = false;
  bool theta = false;
  std::string scale;
  std::string scale_axis = "both";
  int scale_oracle_max = 600;
  std::string solvers;
  double accuracy = 1e-6;
  int jobs = 1;
};

/// --solvers / --accuracy (the solver comparison, docs/bench.md); across MPI ranks the pairs'
/// records are joined with the rest (mpi_bench.cpp).
void set_solver_comparison(const BenchArgs& a, bench::BenchOptions& o) {
  if (a.solvers.empty()) return;
  for (const std::string& name : bench::split_list(a.solvers)) o.solvers.push_back(SolverId::parse(name));
  o.accuracy = a.accuracy;
}

/// Thrown from the progress callback when a stop signal arrived: the bench stops after the
/// step in progress (every thread), writes nothing and leaves an earlier --out DIR as it was.
struct BenchStopped {
  long done = 0, total = 0;
};

/// The bench's options from the command line: the scene, its family and seeds, the starters.
bench::BenchOptions bench_options(const BenchArgs& a, const WarmStarterRegistry& registry) {
  bench::BenchOptions o;
  o.scene = a.scene.load();
  // A family's own evaluation seeds ([family] seeds) apply when --seeds is not given.
  const bool default_seeds = a.seeds == "1..8";
  o.seeds = bench::parse_seed_range(a.quick && default_seeds ? "1"
                             : default_seeds && !o.scene.family.seeds.empty() ? o.scene.family.seeds
                                                                              : a.seeds);
  o.family = !o.scene.family.name.empty() ? o.scene.family.name
             : a.scene.file.empty()        ? "seed"
                                           : std::filesystem::path(a.scene.file).stem().string();
  o.max_sweeps = a.max_sweeps;
  o.budget = a.budget;
  o.warmup_steps = a.warmup_steps;
  o.oracle = !a.no_oracle;
  o.keep_theta = a.theta;
  // The θ rows' temporary file goes to the disk of --out (checked writable before the run).
  if (!a.out.empty()) {
    std::filesystem::path out = std::filesystem::absolute(a.out).lexically_normal();
    if (!out.has_filename()) out = out.parent_path();  // "DIR/"
    o.scratch_dir = out.parent_path().string();
  }
  if (a.steps > 0) o.scene.time.steps = a.steps;
  o.sweeps = a.sweeps > 0 ? a.sweeps : o.scene.solver.sweeps;
  o.tolerance = a.tol;
  o.solver = SolverId::parse(a.solver);
  o.jobs = a.jobs;
  o.env.model_path = a.model;
  set_solver_comparison(a, o);
  if (a.mode == "paired") o.mode = bench::Mode::Paired;
  else if (a.mode == "rollout") o.mode = bench::Mode::Rollout;
  else throw ConfigError("--mode must be 'paired' or 'rollout', got '" + a.mode + "'");
  o.warmstarts = a.warmstarts.empty() ? default_bench_starters(shipped_model(), a.quick) : bench::split_list(a.warmstarts);
  if (!o.oracle) {  // the default list without the oracle starters
    std::vector<std::string> kept;
    for (const auto& n : o.warmstarts)
      if (!registry.make(n, o.env)->uses_oracle() || !a.warmstarts.empty()) kept.push_back(n);
    o.warmstarts = kept;
  }
  return o;
}

/// --scale: the size sweep, its table, and with --out its report (docs/bench.md).
void run_size_sweep(const BenchArgs& a, const bench::BenchOptions& o, const WarmStarterRegistry& registry) {
  std::vector<int> counts;
  for (const auto& item : bench::split_list(a.scale)) {
    std::size_t used = 0;
    int v = 0;
    try { v = std::stoi(item, &used); } catch (const std::exception&) { used = 0; }
    if (used != item.size() || v < 1) throw ConfigError("--scale '" + a.scale + "': expected body counts N1,N2,… >= 1");
    counts.push_back(v);
  }
  bench::ScaleAxis axis = bench::ScaleAxis::Both;
  if (a.scale_axis == "height") axis = bench::ScaleAxis::Height;
  else if (a.scale_axis != "both") throw ConfigError("--scale-axis must be 'both' or 'height', got '" + a.scale_axis + "'");
  std::unique_ptr<bench::ProgressBar> sbar;
  const auto points = bench::run_scale_sweep(o, counts, axis, o.oracle ? a.scale_oracle_max + 1 : 1, registry,
                                             [&](long done, long total, const std::string& note) {
                                               if (done == 1 || !sbar) {  // a new size: a new bar
                                                 if (sbar) sbar->finish();
                                                 sbar = std::make_unique<bench::ProgressBar>("scale", total);
                                               }
                                               sbar->advance(1, note);
                                             });
  if (sbar) sbar->finish();
  std::printf("%s", bench::format_scale_table(points, false).c_str());
  if (!a.out.empty()) {
    const auto files = bench::write_scale_report_directory(points, axis, a.out);  // report_directory.hpp
    std::printf("report: %s/scale.md (%zu files)\n", a.out.c_str(), files.size());
  }
}

/// The bench across threads and ranks; rank 0 prints the table and writes the report.
void run_bench(const BenchArgs& a, const bench::BenchOptions& o, const WarmStarterRegistry& registry) {
  std::unique_ptr<bench::ProgressBar> bar;
  // Across MPI ranks each runs a block of the seeds and rank 0 reports (mpi_bench.hpp).
  DistributedBenchTimes times;
  const SigintGuard stop_signals;  // SIGINT/SIGTERM/SIGUSR1: stop after the current step
  bench::BenchResults r;
  try {
    r = run_bench_across_ranks(o, registry, [&](long done, long total, const std::string& note) {
      if (interrupted()) throw BenchStopped{done, total};
      if (!world().is_root()) return;  // every rank polls for signals, rank 0 draws the bar
      if (!bar) bar = std::make_unique<bench::ProgressBar>("bench", total);
      bar->advance(1, note);
    }, &times);
  } catch (const BenchStopped& s) {
    if (bar) bar->finish();
    // mpirun forwards the signal to every rank; one line (rank 0's) says what happened.
    if (world().is_root())
      std::fprintf(stderr, "deepcontact: bench interrupted by %s after %ld of %ld steps%s; nothing written%s\n",
                   interrupt_signal_name(), s.done, s.total, world().parallel() ? " of rank 0's seeds" : "",
                   a.out.empty() ? "" : (" (" + a.out + " is as it was)").c_str());
    exit_status() = interrupt_exit_status();
    return;
  }
  if (bar) bar->finish();
  if (!world().is_root()) return;
  if (world().parallel())
    std::printf("bench: %d ranks; rank 0 ran its seeds in %.2f s, then waited for, gathered and merged the others' "
                "in %.2f s\n", world().size(), times.run_seconds, times.gather_seconds);
  const auto summary = bench::summarise(r);
  std::printf("%s", bench::format_table(r, summary, false).c_str());
  std::printf("(%zu evaluated steps, %d without contacts skipped; medians over steps; * = oracle starter; %.1f s)\n",
              r.starters.empty() ? 0 : r.starters[0].sweeps_to_tol.size(), r.skipped_steps, r.wall_seconds);
  if (!a.out.empty()) {
    const auto tw = std::chrono::steady_clock::now();
    const std::size_t files = bench::write_report_directory(r, a.out).size();
    std::printf("report: %s/report.md (%zu files, written in %.2f s)\n", a.out.c_str(), files,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - tw).count());
  }
}

void run(const BenchArgs& a) {
  if (!a.out.empty()) bench::check_report_directory(a.out);  // before the bench runs (report_directory.hpp)
  // DIR.lock keeps a second bench off the same DIR (the later rename would replace the first's
  // report with its own); only rank 0 writes the report.
  std::optional<OutputLock> lock;
  if (!a.out.empty() && world().is_root()) lock.emplace(bench::report_lock_target(a.out));
  WarmStarterRegistry registry = all_warm_starters(shipped_model());
  if (a.list) {
    std::printf("%s", registry.help().c_str());
    return;
  }
  const bench::BenchOptions o = bench_options(a, registry);
  if (!a.scale.empty()) run_size_sweep(a, o, registry);
  else run_bench(a, o, registry);
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  auto* cmd = app.add_subcommand("bench", "Compare warm starters on the same scenes and write a report");
  args->scene.add_options(*cmd);
  std::string defaults;
  for (const auto& n : default_bench_starters(shipped_model(), false)) defaults += (defaults.empty() ? "" : ",") + n;
  cmd->add_option("--warmstarts", args->warmstarts,
                  "Comma-separated starters, e.g. zero,builtin,copy:2,sph (default: " + defaults +
                      "; every available one: --list)");
  cmd->add_option("--seeds", args->seeds, "Scene seeds: A..B, or A,B,C (evaluation seeds)")->capture_default_str();
  cmd->add_option("--sweeps", args->sweeps, "PGS sweeps per step (default: the scene's [solver] sweeps, 3000)");
  cmd->add_option("--tol", args->tol, "Convergence threshold on theta [N] (1e-2 N = 1e-4 N*s at dt = 0.01)")
      ->capture_default_str();
  cmd->add_option("--mode", args->mode, "paired (identical LCPs for every starter) or rollout (own trajectories)")
      ->capture_default_str();
  cmd->add_option("--out", args->out,
                  "Write summary.json, results.h5, plots and report.md into this directory: a new or empty one, or an "
                  "earlier bench output (its files are replaced when the new report is complete); a directory holding "
                  "anything else is refused before the run, naming the file in the way (--out . works)");
  cmd->add_option("--solver", args->solver, "Iterative solver under test (pgs-colored, pgs, pgs-assembled, psor, jacobi, nncg)")
      ->capture_default_str();
  cmd->add_option("--model", args->model, "CNN model file for the cnn starter (default: the shipped model)");
  cmd->add_option("--steps", args->steps, "Steps per scene (default: the scene's [time] steps)");
  cmd->add_flag("--quick", args->quick,
                "A short run: one seed, starters zero, builtin, copy, sph (and cnn): ~35 s on an idle core (the default "
                "run: ~10 min on one core, ~5 min with --jobs 2; README \"What to expect\")");
  cmd->add_flag("--list", args->list, "List the available warm starters and exit");
  cmd->add_option("--max-sweeps", args->max_sweeps,
                  "Higher cap: steps not at tol within --sweeps continue up to this many sweeps (sweeps to tol "
                  "reported apart; 0 = off)");
  cmd->add_option("--budget", args->budget, "Fixed sweep budget of the resid@B column (default min(100, sweeps))");
  cmd->add_option("--warmup-steps", args->warmup_steps,
                  "Steps advanced first with builtin + PGS to tol and not evaluated (let a pile settle)");
  cmd->add_flag("--theta", args->theta,
                "Keep every step's per-sweep theta_k in results.h5 (/warmstarters/NAME/theta: ~290 MB for the default "
                "bench; without it only their quartiles per sweep, a few MB)");
  cmd->add_flag("--no-oracle", args->no_oracle,
                "Skip the tight oracle (large scenes): the reference is builtin + PGS to tol/100; oracle starters "
                "are dropped");
  cmd->add_option("--solvers", args->solvers,
                  "Solver comparison: these solvers (e.g. pgs,nncg,newton-sparse) each solve every step from every "
                  "starter's guess (paired mode; report: time and iterations to --accuracy)");
  cmd->add_option("--accuracy", args->accuracy,
                  "Accuracy target R of --solvers: natural-map residual <= R x the heaviest body's weight m g")
      ->capture_default_str();
  cmd->add_option("--jobs", args->jobs,
                  "Seeds run at once, each on its own thread (results equal --jobs 1 bar the timings, which then "
                  "share the cores; make bench uses every core)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--scale", args->scale,
                  "Size sweep: run the scene at these body counts N1,N2,... keeping its shape (writes scale.md/.csv/.png "
                  "with --out)");
  cmd->add_option("--scale-axis", args->scale_axis,
                  "both (keep the aspect ratio: sides x sqrt(N/N0)) or height (keep the width: a deeper pile)")
      ->capture_default_str();
  cmd->add_option("--scale-oracle-max", args->scale_oracle_max,
                  "Size sweep: skip the oracle (as --no-oracle) above this many bodies")
      ->capture_default_str();
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
