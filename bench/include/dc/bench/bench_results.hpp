#pragma once
// What a bench run produced (docs/design.md §6, docs/bench.md): the options and, for every
// step of every evaluation scene and every warm starter, the convergence history θ_k of a
// fixed-sweep PGS run, the sweeps until θ ≤ tol, the time of the guess and of a tolerance-mode
// solve, and at a set of sweep budgets the residual, λ error against the oracle, penetration
// and energy after the step. Filled by bench_runner.hpp, read by bench_summary.hpp and
// bench_statistics.hpp, written by bench_report.hpp; merged across ranks field by field by
// apps/deepcontact/cluster/mpi_bench.cpp. Modes: paired (default) — every starter solves the
// identical LCP of every step of one reference trajectory advanced with λ*; rollout — every
// starter drives its own simulation with its fixed-sweep λ.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dc/bench/theta_rows.hpp"
#include "dc/engine/trajectory_recorder.hpp"
#include "dc/engine/world_def.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc::bench {

enum class Mode { Paired, Rollout };

struct BenchOptions {
  WorldDef scene;                       ///< evaluation scene (its [bodies] seed is replaced per run)
  std::vector<std::string> warmstarts;  ///< starter specs, e.g. {"zero", "builtin", "copy:2"}
  std::vector<std::uint64_t> seeds{1};  ///< scene seeds (each one simulation)
  int sweeps = 3000;                    ///< fixed sweeps of the convergence run
  double tolerance = 1e-2;              ///< θ threshold [N] (= 1e-4 N·s impulse at Δt = 0.01)
  Mode mode = Mode::Paired;
  SolverId solver{SolverKind::PgsColored};     ///< iterative solver under test (`--solver`, parsed there)
  /// Sweep budgets of the speed/accuracy trade (sorted, ≤ sweeps); empty = log-spaced.
  std::vector<int> budgets;
  WarmStartEnv env;
  std::string family;                   ///< scene family named in the report ([family] name / file stem)
  /// Higher cap: a step that does not reach tol within `sweeps` continues (tolerance mode,
  /// from the convergence run's last iterate) up to `max_sweeps` in all; 0 = off.
  int max_sweeps = 0;
  /// Fixed budget of the "residual at B sweeps" column (added to the budgets; ≤ sweeps;
  /// 0 = min(100, sweeps)).
  int budget = 0;
  /// Steps advanced before the evaluation starts (builtin + PGS until tol, nothing recorded):
  /// lets a pile settle, or starts an impact family just before the impact.
  int warmup_steps = 0;
  /// false: no tight oracle (large N). The reference trajectory is then advanced with builtin +
  /// PGS (tol / 100, cap max(sweeps, max_sweeps)), λ errors are against that λ, and starters
  /// that need the oracle (copy, sph, …) are refused.
  bool oracle = true;
  /// results.h5 holds every step's per-sweep θ_k (/warmstarters/NAME/theta, steps × sweeps;
  /// `--theta`): 289 MB for the default bench. Off by default: the file then has only their
  /// quartiles over steps per sweep (/warmstarters/NAME/theta_quartiles, sweeps × 3), what the
  /// convergence plot draws.
  bool keep_theta = false;
  /// Solver comparison (docs/bench.md "Solver comparison"; paired mode only): every solver here
  /// solves every evaluated LCP from every starter's guess (the same λ⁰ for each solver).
  /// Empty = off: the bench runs as without it. (`--solvers`, parsed there.)
  std::vector<SolverId> solvers;
  /// Accuracy target R of the comparison (dimensionless, default 1e-6): a λ is accurate when its
  /// natural-map residual [N] is at most R · max_i(m_i |g|) [N], the heaviest body's weight in
  /// the step's LCP — the residual as a share of the step's largest weight impulse
  /// max_i(m_i |g| Δt) with the residual taken as the impulse residual·Δt. Without gravity
  /// (or without a body of finite mass) the scale is 1 N.
  double accuracy = 1e-6;
  /// Seeds run at once, each on its own thread (≥ 1). The results are those of one thread bar the
  /// timings, which then share the machine's cores and memory: per-step ms rise a little when
  /// jobs approach the core count (docs/bench.md "Parallel seeds"). 1 = one seed after another.
  int jobs = 1;
  /// Folder of the temporary file that holds the θ rows while the bench runs (theta_rows.hpp;
  /// nameless, so nothing stays there after any exit). Empty = $TMPDIR, else /tmp. The command
  /// puts it next to --out DIR (the disk the results go to anyway).
  std::string scratch_dir;
};

/// One (solver, starter) pair of the solver comparison: one entry per evaluated step.
struct SolverPairRecord {
  std::string solver, starter;
  std::vector<std::uint64_t> seed;          ///< scene seed of each evaluated step
  std::vector<int> iterations_to_accuracy;  ///< first iteration (sweep) with accuracy ≤ R; −1 = never
  /// Warm start + solve until accuracy ≤ R [ms]; a step that never gets there: + the whole run
  /// (up to the cap, or until the solver stopped).
  std::vector<double> ms_to_accuracy;
  std::vector<double> total_ms;             ///< warm start + solve to θ ≤ tol (BenchOptions::tolerance) [ms]
  std::vector<double> final_accuracy;       ///< accuracy (residual / weight scale) where the trace ended
  std::vector<double> weight_scale;         ///< max_i m_i |g| of the step [N]
  /// Work of the trace's solve (from λ⁰ until the solver stopped at R·scale/100 or the cap), for
  /// solvers that count it (newton-sparse, prox-newton); −1 for the others: numeric
  /// factorisations, and prox-newton's outer (proximal/Tresca) passes (−1 for newton-sparse).
  std::vector<int> factorizations, outer_passes;
  /// The same solve's work up to the checkpoint where accuracy ≤ R was first reached (the point
  /// ms_to_accuracy is taken at; the whole solve for a step that never got there; 0 for a λ⁰
  /// already at R), −1 for solvers that do not count it: numeric factorisations, and Newton
  /// iterations (prox-newton: iterations_to_accuracy less its lead stage's nncg sweeps).
  std::vector<int> factorizations_to_accuracy, newton_to_accuracy;
  /// The trace of each step: (ms since the warm start began, accuracy) at λ⁰ and at the
  /// checkpoints until R was reached; points trace_offsets[k] … trace_offsets[k+1]−1 are step k's.
  std::vector<std::size_t> trace_offsets{0};
  std::vector<double> trace_ms, trace_accuracy;
};

/// Per starter: one entry per evaluated step (steps with at least one contact row).
struct StarterRecord {
  std::string name;
  bool uses_oracle = false;
  std::vector<std::uint64_t> seed;    ///< scene seed of each evaluated step
  std::vector<int> step;              ///< step number of each evaluated step
  std::vector<int> rows;              ///< LCP rows of each evaluated step
  std::vector<int> sweeps_to_tol;     ///< first k with θ_k ≤ tol; −1 = never within `sweeps`
  std::vector<int> sweeps_to_tol_high;  ///< with max_sweeps > 0: the same with cap max_sweeps (−1 = never)
  std::vector<double> warmstart_ms;   ///< time of initial_guess() less its own oracle solve
  std::vector<double> oracle_ms;      ///< oracle time the starter spent itself (0 if shared)
  std::vector<double> solve_ms;       ///< tolerance-mode PGS solve from λ⁰ until θ ≤ tol
  std::vector<double> sweep_ns_per_row;  ///< fixed-sweep run: time per sweep per row
  std::vector<double> initial_error;  ///< ‖λ⁰ − λ*‖∞ [N]
  /// θ_k, k = 1..sweeps, one row per step (steps × sweeps), on disk: the bulk of the results
  /// (theta_rows.hpp); everything else here is ~0.8 KB per step with the default budgets.
  ThetaRows theta;
  // Trade at the budgets: step-major (steps × budgets).
  std::vector<double> residual;       ///< natural-map residual after B sweeps [N]
  std::vector<double> lambda_error;   ///< ‖λ_B − λ*‖∞ [N]
  std::vector<double> penetration;    ///< max penetration after the step with λ_B [m]
  std::vector<double> energy_error;   ///< E(after step with λ_B) − E(after step with λ*) [J]
};

struct BenchResults {
  BenchOptions options;
  std::vector<int> budgets;           ///< the budgets actually used
  std::vector<std::uint64_t> step_seed;  ///< per evaluated step: scene seed
  std::vector<int> step_index;        ///< per evaluated step: step number
  std::vector<int> step_rows;         ///< per evaluated step: LCP rows (in paired mode)
  std::vector<double> oracle_ms;      ///< per evaluated step: shared oracle solve time (paired)
  std::vector<double> oracle_residual;///< per evaluated step: oracle accuracy [N]
  /// Per evaluated step: wall-clock ms of the stages every starter shares (paired mode: the
  /// reference world's collide, assemble (+ A when the solver needs it) and integrate;
  /// rollout mode: those of the first starter's world). Warm start and solve are per starter.
  std::vector<double> collide_ms, assemble_ms, integrate_ms;
  int skipped_steps = 0;              ///< steps without contacts (nothing to solve)
  std::vector<StarterRecord> starters;
  /// Solver comparison: solver-major, pairs[s · starters + i] = (options.solvers[s], starter i).
  std::vector<SolverPairRecord> pairs;
  double wall_seconds = 0;
  /// Paired mode: the reference trajectory of the first seed (advanced with λ*) and its
  /// scene as TOML, for the report's frame (render_frame.hpp); null in rollout mode.
  std::shared_ptr<TrajectoryRecorder> reference;
  std::string reference_scene;
};

}  // namespace dc::bench
