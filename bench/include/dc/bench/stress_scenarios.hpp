#pragma once
// Extreme scenes (docs/robustness.md): the scene builders and the instrumented stepping loop
// shared by tests/engine/extreme_scene_test.cpp (light versions, asserted) and `deepcontact
// stress` (heavier sweeps, tabulated). Deterministic except for wall time. RunStats:
//  * penetration: the largest circle–circle or circle–wall overlap after each step, by an
//    independent geometric check (the engine's contact list holds only pairs within margin);
//  * energy growth: max_t (E_t − min_{s≤t} E_s), E = kinetic + potential; with e = 0 the
//    dynamics never gain energy, so growth is injected by the solver; the running minimum
//    catches a slow leak followed by a kick;
//  * momentum drift: max_t |P_t − P_0| / Σ m |v_0| (meaningful without walls and gravity);
//  * solver statuses per step with rows, median sweeps and the worst natural-map residual.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dc/engine/body_state.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world_def.hpp"

namespace dc::stress {

// ---- measurements -------------------------------------------------------------------------

/// Largest overlap [m] in `bodies`: max(0, r_a + r_b − |x_a − x_b|) over circle pairs and
/// max(0, r − distance to wall) over the walls that exist (with a shape table: the engine's
/// exact shape narrow phase, −min gap). Uses the uniform-grid broad phase,
/// so it is O(n) like a step. Throws InvalidArgument for a non-finite position.
double max_overlap(const BodyState& bodies, const WorldSection& box);

/// True when every number of the state is finite.
bool state_finite(const BodyState& bodies);

/// Σ m_k v_k [kg·m/s].
Vec2 linear_momentum(const BodyState& bodies);

/// dc::solver_options(def.solver) without per-sweep θ recording (the stress runs read only
/// each step's status, residual and sweeps).
SolverOptions solver_options(const WorldDef& def);

struct RunConfig {
  int steps = 100;
  /// The last `rest_window` steps count as "at rest": rest_penetration is taken over them.
  int rest_window = 0;
  /// Warm starter from dc_warmstart ("zero", "builtin", ...); builtin is the engine's
  /// usual mode and keeps the fine-Δt sweeps affordable.
  std::string warmstart = "builtin";
  /// Stop at the first non-finite number (state or λ) instead of running on garbage.
  bool stop_on_nonfinite = true;
  /// Before stepping, time World::collide() this many times and keep the minimum
  /// (RunStats::collide_min_ms; 0 = don't): the broad-phase scaling measure, robust against
  /// the noise of a shared machine.
  int collide_repeats = 0;
};

struct RunStats {
  int steps = 0;                 ///< steps actually run
  double wall_s = 0;             ///< wall time of the whole run [s]
  double collide_ms = 0;         ///< total time in World::collide (broad + narrow phase) [ms]
  double collide_min_ms = 0;     ///< min over RunConfig::collide_repeats calls of collide() [ms]
  double max_penetration = 0;    ///< worst overlap after any step [m]
  double rest_penetration = 0;   ///< worst overlap over the last rest_window steps [m]
  double energy0 = 0;            ///< E before the first step [J]
  double max_energy_growth = 0;  ///< max_t (E_t − min_{s≤t} E_s) [J]
  /// Σ_k m_k · max_t |v_k(t)| [kg·m/s]: the momentum the run could have lost or gained
  /// (the initial Σ m |v| is 0 for bodies pushed apart from rest).
  double momentum_scale = 0;
  double momentum_drift = 0;     ///< max_t |P_t − P_0| [kg·m/s]
  double max_speed = 0;          ///< largest |v| seen [m/s]
  bool nonfinite = false;        ///< a NaN/Inf appeared in the state or in λ
  int solves = 0;                ///< steps with at least one row
  int converged = 0, sweep_limit = 0, diverged = 0, failed = 0, infeasible = 0, invalid = 0;
  int tolerance_reached = 0;     ///< stopped at θ ≤ tolerance without passing the solution test
  double median_sweeps = 0;      ///< over the steps with rows
  double max_residual = 0;       ///< worst natural-map residual of the returned λ [N]
  int max_rows = 0;              ///< largest LCP of the run
  /// Set when a returned result was inconsistent: residual ≠ natural_residual(λ), a NaN
  /// residual, or a wrongly sized λ (the "no garbage" contract of LcpSolver).
  std::string garbage;
};

/// Steps `world` with `solver`/`options` and the named warm starter, measuring as it goes.
/// Never throws for a numerical failure: a non-finite value ends the run with nonfinite set.
RunStats run_world(World& world, LcpSolver& solver, const SolverOptions& options,
                   const RunConfig& config);

// ---- the stress table ---------------------------------------------------------------------

/// One row of `deepcontact stress`.
struct Scenario {
  std::string family;   ///< "mass ratio", "dt", "column", ...
  std::string params;   ///< the parameters that vary, e.g. "ratio=1e6 heavy on top"
  WorldDef def;
  std::optional<BodyState> state;  ///< explicit initial state (coincident centres)
  RunConfig run;
  // Thresholds of the verdict (documented in docs/robustness.md):
  double penetration_tol = 0;      ///< rest penetration must be ≤ slop + this [m]
  double energy_tol = 0;           ///< energy growth must be ≤ this [J]
  bool check_momentum = false;     ///< drift must be ≤ 1e-9 · momentum scale
  /// Broad-phase scaling row: compare collide_min_ms against the row `linear_ref` (index
  /// into the scenario list, −1 = none) and require ≤ 2 × (count ratio): the factor 2 leaves room for
  /// cache and TLB effects at large body counts (docs/robustness.md).
  int linear_ref = -1;
};

/// The scenario list of `deepcontact stress` (quick = a reduced set for smoke runs).
std::vector<Scenario> stress_scenarios(bool quick);

/// Verdict of one row: "held" or "limit reached: <what>".
/// `ref_s`/`ref_r`: the row named by s.linear_ref and its result (nullptr = no scaling check).
std::string verdict(const Scenario& s, const RunStats& r, const Scenario* ref_s = nullptr,
                    const RunStats* ref_r = nullptr);

}  // namespace dc::stress
