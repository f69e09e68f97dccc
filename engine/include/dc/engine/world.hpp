#pragma once
// The 2D impulse engine: circles, convex polygons and ellipses (dynamic, static or kinematic)
// in a box with up to four walls, stepped by semi-implicit Euler with a velocity-level contact
// LCP (docs/design.md §2, docs/engine.md "One step"). A step is a sequence of stages, each
// callable on its own so that a benchmark can solve the identical LCP from several guesses:
//   collide()    broad (uniform grid) + narrow phase → contacts sorted by key (e > 0: approach
//                velocities, restitution.hpp)
//   assemble()   contact constraints, J (sparse), M⁻¹, b, bounds; A = J M⁻¹ Jᵀ Δt on demand
//   [solve]      any LcpSolver, from any λ⁰ (the warm start)
//   integrate(λ) u ← u + Δt M⁻¹ (F_ext + Jᵀ λ), x ← x + Δt v, θ ← θ + Δt ω (step_outcome.hpp);
//                stores λ in the contacts (previous_contacts()), then appends the bodies that
//                enter at the new time ([[body]] spawn, [inflow]: inflow.hpp)
// step() runs all stages and returns a per-stage profile. With `internal_order = "morton"` the
// stages run on a re-sorted copy of the bodies; everything public stays in creation order and is
// translated lazily on first read, so the const accessors fill caches: such a World is not safe
// to read from two threads at once (docs/engine.md "Engine-internal order"). Any World writes
// the solved λ into its contacts on the first contacts() / previous_contacts() after
// integrate(): those two are not to be called from two threads at once either.
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "dc/core/thread_pacer.hpp"
#include "dc/engine/body_state.hpp"
#include "dc/engine/broad_phase.hpp"
#include "dc/engine/circle_pair_cache.hpp"
#include "dc/engine/contact.hpp"
#include "dc/engine/inflow.hpp"
#include "dc/engine/internal_body_order.hpp"
#include "dc/engine/circle_probe.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/shape_narrow_phase.hpp"
#include "dc/engine/step_outcome.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {

/// Wall-clock milliseconds (steady_clock) spent in each stage of one World::step. Timing
/// only: nothing the step computes depends on it. The trajectory stores it per step as
/// /solver/profile (docs/formats.md), the recorder's own time added as a further column.
struct StepProfile {
  double collide_ms = 0;      ///< collide(): broad phase + narrow phase (+ approach velocities)
  double broad_phase_ms = 0;  ///< of which the broad phase (UniformGridBroadPhase::find_pairs)
  double assemble_ms = 0;     ///< assemble() (+ ensure_assembled_matrix() when the solver needs A)
  double warmstart_ms = 0;    ///< the initial guess λ⁰
  double solve_ms = 0;        ///< the LCP solver
  double integrate_ms = 0;    ///< integrate(λ): bodies, λ stored in the contacts, previous contacts
  /// Sum of the stages (broad_phase_ms is part of collide_ms) [ms].
  [[nodiscard]] double total_ms() const {
    return collide_ms + assemble_ms + warmstart_ms + solve_ms + integrate_ms;
  }
};

struct StepReport {
  int contacts = 0;
  int rows = 0;
  SolveResult solve;
  StepProfile profile;
};

class World {
 public:
  /// Validates `def`, generates the seeded circles and adds the explicit ones.
  /// Throws ConfigError (bad values, overlapping or out-of-box explicit bodies, or a
  /// generator that cannot place `count` circles without overlap).
  explicit World(WorldDef def);
  /// A world with a given body state (e.g. restored from a file); validates `def` only.
  World(WorldDef def, BodyState bodies);

  [[nodiscard]] const WorldDef& def() const { return def_; }
  [[nodiscard]] const BodyState& bodies() const {
    if (bodies_stale_) gather_bodies();
    return bodies_;
  }
  /// Mutable bodies: with an internal order, edits reach the engine's working copy at the
  /// next collide() (every body is copied then; calling this marks the bodies as edited).
  BodyState& bodies() {
    if (bodies_stale_) gather_bodies();
    bodies_edited_ = true;
    return bodies_;
  }
  /// Reserves room in the body arrays for every body the inflow will still add, so that
  /// from now on adding bodies never moves them: pointers into bodies() (Python's numpy
  /// views of World.bodies) stay valid for the rest of the run.
  void reserve_added_bodies() {
    bodies_.reserve(bodies_.size() + static_cast<std::size_t>(inflow_.total() - inflow_.added()));
  }
  [[nodiscard]] int step_index() const { return step_; }
  [[nodiscard]] double time() const { return step_ * def_.time.dt; }

  // ---- stages ----------------------------------------------------------------------
  const std::vector<Contact>& collide();
  const LcpProblem& assemble();
  /// Forms A of the assembled problem if it is not formed yet (for assembled solvers, export).
  const LcpProblem& ensure_assembled_matrix();
  /// λ in the rows of problem() (external order): any contiguous vector (a VectorXd, the
  /// KeptVector of LcpSolver::solve_into) without a copy.
  void integrate(const Eigen::Ref<const Eigen::VectorXd>& lambda);

  // ---- results of the stages ---------------------------------------------------------
  [[nodiscard]] const std::vector<Contact>& contacts() const;
  /// Contacts of the previous step with their solved λ (the built-in warm start's memory).
  [[nodiscard]] const std::vector<Contact>& previous_contacts() const;
  [[nodiscard]] const LcpProblem& problem() const;
  /// out ← the builtin warm start's λ⁰ of problem(): put_matched_lambda(previous_contacts(),
  /// contacts(), problem(), out), bit for bit (the warmstart library's `builtin`), reading the
  /// previous λ where integrate() left them (without building the contacts' λ fields first).
  void builtin_guess_into(KeptVector& out) const;
  /// The broad phase (its last_pair_tests() measures its last run's work; collide() keeps the
  /// circle pairs across steps while the bodies stay near, circle_pair_cache.hpp).
  [[nodiscard]] const UniformGridBroadPhase& broad_phase() const { return broad_phase_; }
  /// Wall-clock time of the broad phase in the last collide() [ms] (timing only).
  [[nodiscard]] double last_broad_phase_ms() const { return broad_phase_ms_; }
  /// Re-sorts of the engine-internal body order so far (0 without one; the first sort at
  /// construction counts): diagnostics of `[bodies] resort_every` / `resort_decay`.
  [[nodiscard]] int internal_order_resorts() const { return resorts_; }
  /// Bodies added during the run ([[body]] spawn, [inflow]; inflow.hpp).
  [[nodiscard]] const Inflow& inflow() const { return inflow_; }
  /// Rows, bodies and μ of each current contact (of the last assemble()).
  [[nodiscard]] const ContactConstraints& constraints() const { return problem().constraints; }
  /// Row of the normal / tangent constraint of contact c (tangent: −1 when its μ = 0).
  [[nodiscard]] int normal_row(int c) const { return constraints()[c].normal_row; }
  [[nodiscard]] int tangent_row(int c) const { return constraints()[c].tangent_row; }
  /// Packs per-contact (λ_n, λ_t) into the row vector of the current problem
  /// (ContactConstraints::scatter; λ_t may be empty when no contact has friction).
  [[nodiscard]] Eigen::VectorXd pack(const std::vector<double>& lambda_n,
                                     const std::vector<double>& lambda_t) const;
  /// What integrate(λ) would do, without doing it (predict_step on the current step).
  void predict(const Eigen::VectorXd& lambda, StepOutcome& out) const;

  // ---- one whole step ----------------------------------------------------------------
  /// Returns λ⁰ for the current (collided, assembled) problem; empty function = zeros.
  using InitialGuess = std::function<Eigen::VectorXd(const World&)>;
  StepReport step(LcpSolver& solver, const SolverOptions& options,
                  const InitialGuess& guess = {});
  /// Initial guesses the engine computes itself.
  enum class WarmStart {
    /// The builtin warm start: the previous step's solved λ of the contact with the same key
    /// (match_contacts_by_key), 0 for new contacts, clamped by project_feasible — bit for bit
    /// the warmstart library's `builtin`. With an internal order it is computed in the internal
    /// rows (previous contacts matched by internal key), with no public view built.
    PreviousLambda,
  };
  StepReport step(LcpSolver& solver, const SolverOptions& options, WarmStart guess);

  // ---- diagnostics -------------------------------------------------------------------
  [[nodiscard]] double kinetic_energy() const;    ///< Σ ½ m v² + ½ I ω² [J]
  [[nodiscard]] double potential_energy() const;  ///< Σ −m g·x [J]
  [[nodiscard]] double max_penetration() const;   ///< max(0, −min gap) over current contacts [m]

 private:
  WorldDef def_;
  /// With an internal order, bodies_, contacts_, previous_ and problem_ are the public views,
  /// refreshed on first read after a stage changed them (the *_stale_ flags): mutable caches.
  mutable BodyState bodies_;
  int step_ = 0;
  mutable std::vector<Contact> contacts_;
  mutable std::vector<Contact> previous_;
  /// Set by integrate(): the solved contacts_ are also the previous step's contacts. The next
  /// collide() swaps them into previous_ instead of integrate() copying every contact (a
  /// 128-byte struct per contact: 6 MB a step at 40,000 bodies, memory-bound).
  bool contacts_are_previous_ = false;
  /// The solved (λ_n, λ_t) of contacts_ and of previous_, packed (world/parts/contact_lambdas.hpp;
  /// without an internal order): integrate() gathers them here, and the *_unstored_ flags say
  /// that the contacts' own fields still wait for them (written on first read of the list).
  std::vector<ContactLambda> lambdas_, previous_lambdas_;
  mutable bool lambdas_unstored_ = false, previous_lambdas_unstored_ = false;
  /// Per-body packed narrow-phase records (speculative reach included) and box half-extent,
  /// and the broad phase's pairs: reused buffers of collide() (no allocation per step).
  std::vector<CircleProbe> probes_;
  std::vector<double> reach_;
  CirclePairCache pair_cache_;  ///< the circle narrow phase's candidate pairs across steps
  mutable LcpProblem problem_;
  UniformGridBroadPhase broad_phase_;
  ShapeNarrowPhase shape_narrow_phase_;  ///< collide() of scenes with a shape table
  double broad_phase_ms_ = 0;
  Inflow inflow_;  ///< appends late bodies at construction and after every integrate()

  /// collide() / assemble() / the step's guess without building the public views.
  void collide_stage();
  void assemble_stage();
  /// The step with `guess` (a user function) or, when it is null, WarmStart::PreviousLambda.
  StepReport step_with(LcpSolver& solver, const SolverOptions& options, const InitialGuess* guess);
  /// The stages of step_with on step_threads_.
  StepReport step_stages(LcpSolver& solver, const SolverOptions& options, const InitialGuess* guess);
  /// Bodies per thread below which the stages run serially.
  static constexpr long kMinBodiesPerThread = 1024;
  /// Broad and narrow phase of a circle-only scene on `bodies` into `out` (sorted by key).
  void collide_circles(const BodyState& bodies, std::vector<Contact>& out);
  /// collide_circles' pair contacts on threads > 1: the jobs count their contacts, then write
  /// them straight into place in `out` after its wall contacts (no lists merged by a copy).
  void place_pair_contacts(int threads, int body_jobs, const std::vector<std::pair<int, int>>& pairs,
                           std::vector<Contact>& out);
  /// Threads of the stages of the step in progress (1 outside step(): the stages called one by
  /// one run serially), chosen by step() from the solver's threads while whole steps pay (the
  /// solver's step pacer, LcpSolver::step_pacer, or pacer_ for a solver that keeps none).
  int step_threads_ = 1;
  /// Whole steps keep their threads while threaded steps take at most kStepPays of the serial
  /// steps' time per unit of work: a step's serial stages make its threaded gain smaller than
  /// the solve's alone, and a stricter ratio would drop threads that gain for a noisy step.
  static constexpr double kStepPays = 0.95;
  ThreadPacer pacer_{kStepPays};
  /// collide_circles' wall contacts per job: 4 lists per job of bodies.
  std::vector<std::vector<Contact>> part_walls_;
  std::vector<InternalBodyOrder::Spread> part_spread_;  ///< the spread of each job of pairs
  std::vector<std::size_t> pair_at_;  ///< place_pair_contacts' offsets of each job's contacts in `out`
  /// integrate() on the problem the stages solved (internal rows when there is an order).
  void integrate_solved(const Eigen::Ref<const Eigen::VectorXd>& lambda, const Eigen::VectorXd* position_lambda = nullptr);
  /// The relax pass (`[solver] relax_sweeps`, world/parts/relax_pass.hpp) after the solve in
  /// rep: sweeps without the position bias from its λ; rep then reports the relaxed λ.
  void relax_solve(LcpSolver& solver, const SolverOptions& options, LcpProblem& solved, StepReport& rep);

  // ---- engine-internal body order ([bodies] internal_order; empty/unused when "none") ----
  bool internal_ = false;  ///< steps_in_internal_order(def_.bodies.internal_order, initial bodies)
  [[nodiscard]] bool has_internal_order() const { return internal_; }
  /// The bodies the stages work on: bodies_, or the internally ordered copy.
  BodyState& working_bodies() { return internal_ ? order_.state() : bodies_; }
  /// Brings order_ up to date with bodies_ (appended bodies, user edits) and re-sorts it when
  /// the order has decayed (decayed_) or resort_every steps after the last re-sort; previous
  /// contacts are re-keyed to the new order.
  void update_internal_order();
  /// Lazy public views (internal order only): bodies by external index; this step's contacts
  /// in external key order (internal_of_contact_: the internal contact of each); the previous
  /// step's; the problem: the public contacts assembled on assembly_bodies_ (the bodies by
  /// external index as they were at assemble(): pre_* keeps x, v, ω across integrate()).
  void gather_bodies() const;
  const std::vector<int>& public_order() const;
  InternalBodyOrder order_;
  std::vector<Contact> internal_contacts_;  ///< this step's contacts in internal order
  std::vector<Contact> internal_previous_;  ///< the previous step's, keyed in the current internal order
  LcpProblem internal_problem_;             ///< their LCP (rows follow space)
  Eigen::VectorXd internal_lambda_;         ///< integrate(λ)'s λ translated (reused)
  KeptVector relax_b_;                      ///< the relax pass's b with bias
  Eigen::VectorXd relax_lambda_, relax_dl_;  ///< the relax pass's λ_b, scratch
  KeptVector lambda0_, solved_lambda_;       ///< step()'s λ⁰ and λ (storage kept as the rows change)
  std::vector<long> warm_starts_;            ///< the threaded builtin warm start's scratch
  Eigen::VectorXd impulse_;                  ///< integrate's Δt·Jᵀλ (storage reused)
  mutable std::vector<int> internal_of_contact_;
  std::vector<Vec2> pre_position_, pre_velocity_;
  std::vector<double> pre_omega_;
  mutable BodyState assembly_bodies_;
  mutable bool bodies_stale_ = false, contacts_stale_ = false, previous_stale_ = false, problem_stale_ = false,
               order_stale_ = false;
  bool bodies_edited_ = true;  ///< bodies() was called mutably since the last copy
  /// internal_problem_'s constraints are those of internal_contacts_ (assembled since the
  /// last collide): public_order() reads the keys from them.
  bool internal_assembled_ = false;
  int last_resort_step_ = -1;  ///< step_ of the last re-sort (−1: never)
  int resorts_ = 0;
  /// Decay of the internal order: Σ |i − j| and count of the pair contacts of the last
  /// collide() (counted in collide_circles), and those of the lowest mean since the last re-sort.
  InternalBodyOrder::Spread spread_, spread_at_resort_;
  bool spread_baseline_due_ = true;  ///< the next collide() sets spread_at_resort_
  bool decayed_ = false;             ///< re-sort at the next collide()
};

/// Generated (seeded Gaussian, rejection-sampled) plus explicit circles of a definition.
BodyState make_bodies(const WorldDef& def);

/// Stable 64-bit FNV-1a hash of the full body state (bit patterns), for determinism tests.
std::uint64_t state_hash(const BodyState& bodies);

}  // namespace dc
