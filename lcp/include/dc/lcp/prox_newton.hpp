#pragma once
// "prox-newton": hard-Coulomb accuracy through convex subproblems only (docs/solvers.md
// "prox-newton"). Outer pass k freezes the friction bounds at s = μ max(0, λ_n^k) (Tresca) and
// adds a proximal term ½ δ_k ‖λ − λ^k‖²: the subproblem
//     min_λ ½ λᵀ(A + δ_k I)λ + (b − δ_k λ^k)ᵀλ,   λ_n ≥ 0, |λ_t| ≤ s_t, fixed bounds elsewhere,
// is a strongly convex box QP. Its solution becomes λ^{k+1}; s and δ are updated (δ shrinks
// while the hard residual falls, grows when it does not). A fixed point with δ > 0 solves the
// hard problem: λ = λ^k makes the proximal term vanish and s = μ λ_n the Coulomb bounds.
//
// The subproblem is solved
//   * in body space when the problem carries J and M⁻¹ (LcpProblem::has_jacobian()): in
//     velocity changes v [m/s], minimising ½ vᵀ(M/Δt)v + Σ_i φ_i((J v + c)_i), c = b − δλ^k,
//     with φ_i the half-quadratic y²/(2δ)·[y < 0] on normal rows and the Huber friction loss
//     (y²/(2δ) for |y| ≤ sδ, s|y| − ½δs² beyond) on friction rows; Newton on the SPD
//     H = M/Δt + Jᵀ D J (D_ii = 1/δ on the quadratic pieces), 3 unknowns per body, CHOLMOD with
//     the analysis kept while the pattern holds (the factor while D and δ do), and an exact line
//     search on the piecewise quadratic cost; λ_i = clamp(−y_i/δ, lo_i, hi_i); with
//     `coupled_bounds` the friction bounds follow the iterate (the hard proximal subproblem,
//     body_newton.hpp); the direction by CG preconditioned with a kept factor of an earlier H
//     while CG converges within `stale_factor_iterations` (stale_pcg.hpp);
//   * in the dual form otherwise (problems from files): the box LCP w = (A + δI)λ + c with the
//     frozen bounds by newton-sparse's semismooth Newton (no friction coupling: one CHOLMOD
//     factorisation per iteration, the analysis kept across passes).
// With `exact_cone` (body space) the passes are instead proximal steps on the exact 2D friction
// cone with de Saxcé's shift of the normal velocities (docs/solvers.md "Exact-cone passes").
// Before the passes, in body space, the lead stage: nncg sweeps from the guess while their best
// hard residual falls at least `lead_window_gain`-fold per `lead_window` chunks, `lead_sweeps` at
// most. Once the row modes repeat between two passes, `finish_iterations` newton-sparse iterations
// on the hard problem; when the passes stop (max_stalls passes without a new best, or max_outer)
// above the target, with `body_finish` coupled body-space passes from the best iterate, then
// the proximal-point route from the best iterate (`proximal_finish`); then, on
// small contact problems, Lemke's pivoting on the problem as a standard LCP (`pivot_rows`),
// then nncg as the safeguard, then (opt-in, `local_pivot_rows`) Lemke on the worst rows'
// contacts and their neighbours with the rest fixed, then, on problems with friction, the
// continuation in μ (`continuation_stages`: solves with μ scaled up in stages, then of the
// problem itself). SolveResult::message names the part that finished ("prox",
// "newton-sparse finish", "proximal newton-sparse finish", "lemke pivoting finish", "nncg
// safeguard" or "mu continuation finish") and the counts; `sweeps` counts
// Newton iterations (inner and both finishes; the safeguard's sweeps are in the message).
// `factorizations` counts every numeric factorisation (passes and both finishes).
//
// On degenerate problems (degenerate_rows) the lead stage runs one probe of coupled passes at
// one of its looks (probe_sweeps), which ends the solve when it reaches the target.
//
// Status: Converged only when the natural residual of the HARD problem at the returned λ is
// ≤ target (options.tolerance [N] when > 0, else exact_tolerance·max(1, ‖b‖∞)); SweepLimit when
// the Newton iteration budget (options.max_sweeps) ran out; Failed otherwise (stalled).
#include <memory>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/proximal_point.hpp"

namespace dc {

/// The sweeps of prox-newton's lead stage (ProxNewtonDef::lead_sweep).
enum class ProxLeadSweep {
  Natural,  ///< "nncg": pgs's matrix-free sweep in row order
  Colored,  ///< "nncg-colored": pgs-colored's colour-ordered SIMD batches (pgs_colored.hpp)
  Auto,     ///< Colored from ProxNewtonDef::lead_colored_rows rows on, Natural below
};

struct ProxNewtonDef {
  /// Body space: the lead stage, nncg sweeps from the guess before the passes, at most (default
  /// 10000; 0 = none). One nncg run (its momentum kept throughout), its hard residual looked at
  /// every 50 sweeps (a chunk), stops at the target, at this cap, or when the best hard residual
  /// stops falling (lead_window). Short of the target, the Newton part runs
  /// from its best iterate first (lead_gain) and from the guess when that misses the target (its
  /// best iterate stays a candidate for the answer).
  /// On loose and small piles nncg reaches the target in tens to a few hundred sweeps; on 1,000-
  /// body impacts and polydisperse piles it gets there in thousands, each sweep far cheaper than
  /// a Newton iteration (a few thousand sweeps cost less than one Newton part on such a pile).
  /// On 250-body impacts nncg still converging at the window's rate can need several thousand
  /// sweeps to the target, and on those steps they cost less than the Newton part from an
  /// earlier iterate.
  int lead_sweeps = 10000;
  /// Which nncg runs the lead stage: Natural ("nncg"), Colored ("nncg-colored": the same
  /// momentum on pgs-colored's sweeps, cheaper per sweep on large problems, in colour order and
  /// with a per-solve set-up; its colouring is kept by the solver object from solve to solve), or
  /// Auto (default): Colored on problems of at least `lead_colored_rows` rows. Both make the same
  /// sweeps to the target (the ordered colouring follows the rows' order); they differ in rounding
  /// and in cost. The safeguard stays "nncg".
  ProxLeadSweep lead_sweep = ProxLeadSweep::Auto;
  /// Auto's threshold (default 500 rows): below it the colour batches are mostly padding and the
  /// set-up is a large share of a sweep, and nncg is the cheaper lead (the box pile's ≈ 260 rows);
  /// impacts of 250 bodies (≈ 900 rows) and more run the colored lead cheaper
  /// (docs/solvers.md "nncg-colored").
  int lead_colored_rows = 500;
  /// The lead stage goes on while its best hard residual falls at least `lead_window_gain`-fold
  /// over the last `lead_window` chunks (defaults 16, i.e. 800 sweeps, and 2), and during the
  /// first `lead_window` chunks pro rata from the guess's (gain^(n/window) after chunk n: a stage
  /// that gains little from the start, as from an iterate nncg already polished in the oracle,
  /// hands over after a chunk or two). nncg's residual is not
  /// monotone: converging on mid-sized piles, it climbs for up to hundreds of sweeps between new
  /// bests, so a shorter window hands over piles nncg would finish; on deep settled piles it
  /// falls less than 2-fold in 800 sweeps. lead_window = 0: the rate rule instead (stop at a
  /// chunk without a new best, or when the rate since the first chunk would not reach the
  /// target within lead_sweeps), which hands over after a few chunks on those mid-sized piles.
  int lead_window = 16;
  double lead_window_gain = 2.0;
  /// lead_window_gain on problems of more than `lead_window_bodies` bodies, where the window
  /// grows (default 1.3; > 1): on 250-body impact steps nncg often still falls 1.3–2-fold per
  /// window and reaches the target for less than the Newton part's factorisations cost, whose
  /// time goes to the proximal finish's fallback sweeps and refactorisations rather than to
  /// quadratic convergence. On box piles (60 bodies, below the threshold) the Newton part from
  /// nncg's iterate finishes sooner, so there the window keeps lead_window_gain.
  double lead_window_gain_above = 1.3;
  /// The lead stage also hands over after this many chunks in a row without a new best hard
  /// residual (the stall rule; 0 = none), scaled with the bodies as lead_window
  /// (lead_window_bodies). nncg's best sits exactly still on such plateaus: on box piles
  /// (two-point manifolds, more rows than velocity unknowns) it either leaves one within a few
  /// chunks or stays there until the window rule ends the stage, and the Newton part from the
  /// plateau's iterate is what reaches the target.
  int lead_stall_chunks = 0;
  /// Degenerate problems, in body space: at least `degenerate_rows` contact rows per velocity
  /// unknown (J's columns; default 1.3): box piles' two-point manifolds (1.36–1.58 on
  /// scenes/box_pile.toml) make pairs of nearly parallel rows and a rank-deficient A; impacts and
  /// deep piles of circles have 1.21–1.27. On them the lead stage takes the stall rule with
  /// `degenerate_stall_chunks` chunks (default 6; 0: lead_stall_chunks as elsewhere) and the
  /// proximal finish's newton-sparse solves their fallback sweeps with NNCG's momentum
  /// (`degenerate_fallback_momentum`, default true; NewtonSparseDef::fallback_momentum): there
  /// the Newton steps fail on the degenerate row modes and plain PGS batches of up to a thousand
  /// sweeps carry the iterate. On impacts the momentum costs a reached step (its batches lead to
  /// other row modes), so it stays off there. The stall rule ends the stage after 6 chunks
  /// without a new best hard residual (degenerate_stall_chunks = 6; 0 = lead_stall_chunks): on
  /// box piles it saves the plateau's sweeps where the Newton part follows anyway, which the
  /// window rule (lead_window) would sweep on for up to 16 chunks; it also ends some plateaus
  /// nncg would have left and reached the target from, at a higher cost there.
  double degenerate_rows = 1.3;
  int degenerate_stall_chunks = 6;
  bool degenerate_fallback_momentum = true;
  /// Degenerate problems (degenerate_rows): one probe during the lead stage (probe_count). At
  /// the first look at or after `probe_sweeps` sweeps (default 100; 0 = none) within
  /// `probe_reach`, coupled body-space passes (the hard proximal subproblem of `coupled_bounds`,
  /// δ from probe_shift, no newton-sparse finish) run from the best iterate so far for at most
  /// `probe_iterations` Newton iterations in all (default 4). When they reach the target the solve ends there; otherwise the lead's
  /// nncg run goes on untouched (its momentum kept) and every later part sees the solve as
  /// without the probe, the probe's best iterate staying a candidate for the answer. On box
  /// piles nncg often sits on a plateau after a hundred sweeps from which the coupled passes
  /// reach the target in one or two iterations while the lead would sweep on until its window
  /// rule ends it; a missed probe costs its few iterations (one factorisation with its
  /// analysis, GMRES for the coupled directions).
  int probe_sweeps = 100;
  int probe_iterations = 4;
  /// The probe runs only at a look whose best hard residual is within `probe_reach` times the
  /// target (default 100; 0 = at the first look at or after probe_sweeps whatever the best):
  /// the coupled passes converge locally, and in probe_iterations Newton iterations they reach
  /// the target from an iterate whose row modes are nearly right, not from one of nncg's
  /// plateaus far above it, where the probe costs its factorisation and GMRES directions and
  /// misses. A look above the reach leaves the probe for a later look.
  double probe_reach = 100;
  /// Probes per solve at most (default 1; with probe_sweeps > 0). A later probe runs at a look
  /// whose best hard residual is at least `probe_refall`-fold below the best where the probe
  /// before it ran (and within probe_reach): a missed probe leaves nncg's run going, and where
  /// nncg falls on from there the coupled passes from its later iterate start nearer the row
  /// modes of the answer, while a plateau (no such fall) makes no second probe.
  int probe_count = 1;
  double probe_refall = 10;
  /// The probe's first δ relative to max A_ii (default 1e-3; 0 = initial_shift). The probe
  /// starts within probe_reach of the target, where the row modes are nearly those of the
  /// answer: a proximal step at the frozen passes' initial_shift (far from the solution, where
  /// a large δ keeps the subproblem well posed) moves λ less than the probe's few iterations
  /// need, and its passes end a factor above the target; a smaller δ reaches it from an
  /// earlier look. Much smaller δ makes the coupled subproblem as hard as the hard problem
  /// itself and its Newton iterations miss within the probe's count.
  double probe_shift = 1e-3;
  /// Degenerate problems (degenerate_rows): drift jumps of the lead stage at most (default 16;
  /// 0 = none). Where w has a part on the free rows outside A's range (closed contacts that
  /// cannot all hold with the friction they stick with), nncg's sweeps drift along A's null
  /// space: λ changes by the same vector d every sweep, w not at all, and the hard residual
  /// sits on a plateau (a friction row at its bound lags its normal row's drift) until some row
  /// meets a bound, after hundreds to thousands of sweeps on box piles. When the changes of
  /// the last two sweeps before a look agree to `degenerate_drift_linearity` (default 10 %,
  /// ‖d_k − d_{k−1}‖∞ ≤ 0.1‖d_k‖∞), λ jumps along d_k to the first row's bound (a contact
  /// opens, a friction row meets or leaves ±μ λ_n) and nncg starts afresh from there. Only
  /// where the lead sweeps in natural order (nncg; the drift is watched at every sweep).
  int degenerate_drift_jumps = 16;
  double degenerate_drift_linearity = 0.1;
  /// lead_window holds for problems of up to this many bodies (J's columns / 3; default 64);
  /// above, the window grows as √(bodies / lead_window_bodies) (0 = never): a Newton
  /// iteration's factorisation costs about √n nncg sweeps more on n bodies (nested dissection on
  /// a planar contact graph), so on larger piles nncg is worth running longer before the Newton
  /// part. On box piles (60 bodies) the Newton part from a 16-chunk lead finishes in 2
  /// factorisations; on 250-body impacts nncg often reaches the target within 32 chunks where
  /// it falls less than 2-fold over 16, and the Newton part from there costs more than those
  /// sweeps.
  double lead_window_bodies = 64;
  /// The proximal finish of the Newton part from the lead stage's iterate stops when its best
  /// hard residual fell less than 2-fold over this many outer iterations
  /// (ProximalPointDef::progress_window; default 20; 0 = finish_route's own setting): the
  /// Newton part from the guess follows, so a stalled finish hands over early.
  int lead_finish_window = 20;
  /// In that finish, newton-sparse's fallback PGS sweeps after failed steps double at most this
  /// many times (NewtonSparseDef::fallback_doublings; default 8, finish_route's own; a negative
  /// value keeps finish_route's): the Newton part from the guess follows with its own setting,
  /// so a bound here costs no reached step. A tighter bound trades families: it spares box
  /// piles' failing first parts tens of thousands of sweeps, but on 1,000-body impacts it moves
  /// the point where the target is reached from the first part to the part from the guess.
  int lead_fallback_doublings = 8;
  /// In that finish, a newton-sparse solve stops once a batch of its fallback PGS sweeps at the
  /// cap (2^doublings × fallback_sweeps) leaves the residual above this fraction of its value
  /// before the batch (NewtonSparseDef::fallback_cap_fall; default 0.5; 0 = finish_route's own
  /// setting): further batches would repeat that slow one. On box piles damped Newton steps
  /// then creep down a fraction of a percent per iteration behind a thousand sweeps each, and
  /// the route's next shift or the Newton part from the guess converges sooner; where the
  /// doubled sweeps pay (1,000-body impacts) they halve the residual before the cap.
  double lead_fallback_cap_fall = 0.5;
  /// In that finish, a newton-sparse solve stops (failed) after this many iterations in a row
  /// without a new best residual (NewtonSparseDef::max_stalls; default 0: finish_route's own).
  /// A small limit (5) makes the route give up a too-small δ sooner, which spares box piles
  /// hundreds of stalled iterations, but costs impacts the steps where a long stalled solve
  /// is what reaches the target.
  int lead_newton_stalls = 0;
  /// In that finish, the first δ relative to max_i A_ii (ProximalPointDef::initial_shift;
  /// default 1e-4; 0 = finish_route's own, 1e-6). The lead stage hands over where nncg stalls,
  /// often at row modes the small-δ inner solves do not recover from: there they fail after
  /// tens of iterations and refactorisations each, and the route reaches 1e-4 (or its floor)
  /// after two of them. From the guess the finish keeps finish_route's δ.
  double lead_initial_shift = 1e-4;
  /// The proximal finish of the Newton part from the guess starts at the failure floor of δ
  /// that finish of the Newton part from the lead stage's iterate ended with
  /// (ProximalPointDef::initial_floor; default false: at finish_route's own initial_shift).
  /// The shifts below that floor failed there, and their inner solves fail again from the guess.
  bool guess_route_from_floor = false;
  /// In the proximal finish of the Newton part from the guess after that first part: the route
  /// stops after `guess_floor_stalls` outer iterations at a raised δ floor without a new best
  /// hard residual (ProximalPointDef::floor_stalls; default 30; 0 = finish_route's own; the
  /// finishes after it follow): on impacts and deep piles that part otherwise spends up to
  /// max_outer passes at a δ floor of 1e-4 to 1e-3; 10 stalls stopped deep settled piles that
  /// reach the target after a plateau. Its newton-sparse solves stop after a fallback batch at
  /// the cap that leaves the residual above `guess_fallback_cap_fall` of its value before the
  /// batch (NewtonSparseDef::fallback_cap_fall; default 0: finish_route's own, none): 0.5 saves
  /// factorisations on impacts and deep piles but costs the oracle's hard steps their accuracy.
  /// Calls without a first part keep finish_route.
  double guess_fallback_cap_fall = 0;
  int guess_floor_stalls = 30;
  /// That first Newton part runs only when the lead stage lowered the hard residual at least
  /// this many times (default 100): a stage that gained less (the oracle's call, after its own
  /// nncg stage) leaves the Newton part as without it, its best iterate a candidate only.
  double lead_gain = 100.0;
  /// First proximal weight δ_0 relative to max_i A_ii (dimensionless, default 1e-2).
  double initial_shift = 1e-2;
  /// Smallest and largest δ relative to max_i A_ii (defaults 1e-6 and 1e2). Body space reads
  /// λ = −y/δ from velocities: a smaller δ amplifies their round-off by 1/δ.
  double min_shift = 1e-6;
  double max_shift = 1e2;
  /// δ shrinks by this factor after a pass that lowered the hard residual, and grows by it after
  /// one that did not (default 10).
  double shrink = 10.0;
  /// Outer (proximal/Tresca) passes at most (default 100).
  int max_outer = 100;
  /// Newton iterations per subproblem at most (default 30).
  int inner_iterations = 30;
  /// Of those, in body space at most (default 8): on the engine's piles a body-space pass that
  /// has not met its tolerance within a few iterations rarely lowers the hard residual, and the
  /// proximal finish starts from the best iterate either way.
  int body_inner_iterations = 8;
  /// Subproblem accuracy: its own natural residual [N] relative to max(hard target, best hard
  /// residual so far) (inexact proximal point; default 1e-2).
  double inner_tolerance = 0.01;
  /// Newton iterations of the newton-sparse finish once the modes repeat (default 3; 0 = none).
  int finish_iterations = 3;
  /// Body space: the budget of the Newton part from the lead stage's iterate, in numeric
  /// factorisations (default 4; 0 = none), when the lead stage's best hard residual still fell
  /// at least `newton_budget_lead_fall`-fold (default 1.75) over its last window (lead_window;
  /// within the first window, the fall from the guess scaled to a window): nncg was converging,
  /// only slower than the window asks (above lead_window_bodies, with lead_window_gain_above
  /// below this fall as by default, a stage stopped by its cap while still converging). That
  /// part stops once it has made newton_budget factorisations since it began or since the best
  /// hard residual of the whole solve last fell at least `newton_budget_gain`-fold (default 2),
  /// and nncg goes on from the best iterate of
  /// the lead stage and that part (the safeguard, its sweeps counted in safeguard_sweeps); the
  /// Newton part from the guess runs only when nncg misses the target too. Checked after every
  /// pass and every outer iteration of the proximal finish (ProximalPointDef::stop_after), so
  /// the part overruns by one inner solve: asked after every inner Newton iteration instead, the
  /// budget also stopped impact steps whose first part reaches the target within that solve.
  /// On 250-body impacts the lead stage can hand over where nncg still converges at nearly the
  /// window's rate, and a Newton part that creeps down a few percent per factorisation (each
  /// costing as much as many nncg sweeps) spends tens of them before the safeguard. A smaller
  /// budget also stops the parts that reach the target after a short stall, where nncg does not
  /// reach it; without the gate it stops deep settled piles' first parts, whose nncg stalls
  /// (falls far less over a window) and whose Newton part from the guess costs more than the
  /// first part would have.
  int newton_budget = 4;
  double newton_budget_gain = 2.0;
  double newton_budget_lead_fall = 1.75;
  /// nncg sweeps of the safeguard (default 10000; 0 = none): on impacts the Newton parts can
  /// end just above the target on steps that nncg alone reaches only after many thousands of
  /// sweeps, each far cheaper than a Newton iteration.
  int safeguard_sweeps = 10000;
  /// Solve the subproblem in body space when the problem has J (default true; false = dual
  /// form always).
  bool body_space = true;
  /// Body space: the subproblem's friction bounds follow the iterate inside the Newton loop
  /// (s = μ max(0, λ_n) of the same λ: the hard proximal subproblem, semismooth Newton with the
  /// friction coupling, body_newton.hpp) instead of staying frozen at the pass's centre
  /// (default false: on the engine's piles its passes take more Newton iterations than the
  /// frozen passes and the proximal finish they hand over to).
  bool coupled_bounds = false;
  /// Body space: a Newton direction is first sought by conjugate gradients on H preconditioned
  /// with the kept (stale) Cholesky factor of an earlier H, and H is refactorised only when CG
  /// has not met its tolerance within this many iterations (default 25; 0 = refactorise
  /// whenever D or δ changed). H_new − H_old = Jᵀ(D_new − D_old)J has the rank of the rows that
  /// changed mode, so CG with the old factor converges in about that many iterations.
  int stale_factor_iterations = 25;
  /// Body space: after the frozen passes, when the target is not reached, coupled passes (the
  /// hard proximal subproblem of `coupled_bounds`) from the best iterate, before the dual
  /// proximal finish (default false). δ starts at initial_shift and stays while each pass lowers
  /// the hard residual at least 4-fold; slower passes shrink it, failed ones grow it.
  bool body_finish = false;
  /// Newton iterations of those coupled passes at most, in all (default 100).
  int body_finish_iterations = 100;
  /// Body space: the exact-cone outer loop instead of the Tresca passes (default false). Pass k
  /// solves, in velocities, the proximal step of Anitescu's cone problem with the normal
  /// velocities shifted by de Saxcé's μ|w_t^k|: F ∋ λ ⊥ Aλ + b + ŝ + δ(λ − λ^k) ∈ F* with F the
  /// exact 2D friction cone, by Newton on ½ vᵀ(M/Δt)v + Σ_c ‖P_F(−y_c)‖²/(2δ) (MuJoCo's and Drake
  /// SAP's cost; H = M/Δt + Jᵀ G J with a 2×2 G per contact; the exact line search); a fixed point
  /// is an exact Coulomb solution (cone_passes.hpp). The passes stop after `cone_max_stalls`
  /// passes without a new best hard residual, or `max_outer`; the finishes below follow as
  /// after the Tresca passes. Problems without the cone form (a friction row whose normal row
  /// does not have bounds [0, +∞)) take the Tresca passes.
  bool exact_cone = false;
  /// First δ of those passes relative to max_i A_ii (default 1e-3); δ shrinks by `cone_shrink`
  /// after every solved following pass (every solved pass without `cone_follow_shift`), down to
  /// `cone_min_shift`, and grows by it after one that was not solved (defaults 3 and 1e-6).
  double cone_shift = 1e-3;
  double cone_shrink = 3.0;
  double cone_min_shift = 1e-6;
  /// Newton iterations per frozen-shift exact-cone pass at most (default 30: the first passes
  /// from a warm start take 10–20 on the engine's piles).
  int cone_inner_iterations = 30;
  /// Exact-cone pass accuracy: its natural residual [N] relative to max(hard target, best hard
  /// residual so far) (default 0.1).
  double cone_inner_tolerance = 0.1;
  /// Exact-cone passes: de Saxcé's shift follows the Newton iterate inside each pass (the pass
  /// solves the proximal step on the exact Coulomb problem; GMRES on the non-symmetric Jacobian
  /// preconditioned with H's factor, cone_newton.hpp) instead of staying at the pass's start
  /// (default true), once a frozen pass was solved within `cone_follow_after` Newton iterations
  /// (default 4; 0: from the first pass); back to frozen passes after a following pass that was
  /// not solved or did not lower the best hard residual.
  bool cone_follow_shift = true;
  int cone_follow_after = 4;
  /// Newton iterations per following pass at most (default 8): far from a solution the
  /// following pass's semismooth Newton may not converge, and a failed pass is abandoned early.
  int cone_follow_iterations = 8;
  /// Exact-cone passes: also switch to following passes after a solved frozen pass once the best
  /// hard residual is ≤ this fraction of the start's (default 0: by cone_follow_after alone).
  double cone_follow_below = 0;
  /// Exact-cone following passes: a trust region on the shift, |ŝ_n(v) − ŝ_n^k| ≤ τ·m with m the
  /// shift's change over the last accepted pass (cone/shift_trust.hpp). τ starts at
  /// `cone_trust_radius` (default 4; 0: no trust region, the shift follows unbounded and one
  /// unsolved or non-improving following pass goes back to frozen passes), grows by
  /// `cone_trust_grow` (4) after a pass that cut the best hard residual 4-fold, shrinks by it
  /// after a rejected pass (its iterate is dropped for the best), and `cone_trust_retries` (2)
  /// rejections in a row go back to frozen passes.
  double cone_trust_radius = 4;
  double cone_trust_grow = 4;
  int cone_trust_retries = 2;
  /// With the trust region, δ does not shrink back to the δ of a rejected following pass until
  /// the best hard residual has fallen to `cone_trust_forget` (0.1) of the best at the rejection.
  double cone_trust_forget = 0.1;
  /// With the trust region, a following pass (solved or not) is accepted unless its hard residual
  /// rose above `cone_trust_accept` (10) times the best before it: the proximal step on the exact
  /// problem makes progress even where the hard residual rises for a pass.
  double cone_trust_accept = 10;
  /// Anderson acceleration depth of the exact-cone passes' outer map λ^k ↦ λ^{k+1} (anderson.hpp;
  /// default 0: none).
  int cone_anderson = 0;
  /// Exact-cone passes in a row without a new best hard residual before they stop (default 3:
  /// with the trust region a rejected following pass restarts from the best iterate, and passes
  /// that stay above the best for longer sit on a plateau the finishes cross in fewer
  /// factorisations).
  int cone_max_stalls = 3;
  /// Passes without a new best hard residual before the outer loop stops (default 1): the
  /// frozen-bound (Tresca) fixed point converges linearly at best, and once a pass fails to
  /// improve, a further one rarely does (on piles with more contact rows than degrees of
  /// freedom λ_n moves along A's null space and the frozen bounds go stale): the proximal
  /// finish takes over.
  int max_stalls = 1;
  /// Dual form: once δ is at min_shift, a pass that lowers the best hard residual by less than
  /// this factor also counts as a stall (default 0.5): there the passes converge linearly at that
  /// rate or worse, and the proximal finish converges faster from the same iterate.
  double pass_progress = 0.5;
  /// After the passes, when the target is not reached: the proximal-point route
  /// (solve_proximal_point: newton-sparse on A + δI around λ_k, bounds moving with λ_n) from the
  /// best iterate (default true). Its iterations count in the budget and in `finish_newton`.
  bool proximal_finish = true;
  /// Settings of that route in body space: its defaults except δ_0 = 1e-6·max A_ii,
  /// newton-sparse's own inexact GMRES forcing (krylov_forcing = 1e-2): it starts near the
  /// solution, where inexact directions cost fewer GMRES iterations and the proximal outer loop
  /// absorbs their error. Its stall limit stays off (max_stalls = 0): on deep settled piles the
  /// route improves again after long plateaus and reaches the target only when allowed its
  /// outer iterations. Directions by GMRES with a kept factor first (stale_factor_iterations =
  /// 30, NewtonSparseDef): near the solution few rows change mode between iterations and δ
  /// stays put for many outer iterations, so most iterations need no factorisation. GMRES's
  /// inner products in lanes (NewtonSparseDef::lane_dot): on deep piles the Gram–Schmidt of the
  /// route's many Krylov directions is a large part of its time.
  ProximalPointDef finish_route = [] {
    ProximalPointDef d;
    d.initial_shift = 1e-6;
    d.newton_sparse.krylov_forcing = 1e-2;
    d.newton_sparse.stale_factor_iterations = 30;
    d.newton_sparse.lane_dot = true;
    d.max_stalls = 0;
    return d;
  }();
  /// Settings of that route in the dual form (problems without J): those of finish_route and
  ///   * δ ≥ 1e-7·max A_ii: on Siconos' granular files the inner solves at 1e-8 cycle between
  ///     row modes and fail;
  ///   * inexact inner solves (inner_forcing = 0.1: each to a tenth of the best hard residual):
  ///     far from the solution the shift term dominates the hard residual, and solving the
  ///     shifted problem further does not move the next centre further;
  ///   * at most 30 GMRES iterations per direction (krylov_max): where the row modes are still
  ///     wrong the line search rejects the direction whatever its accuracy, and the PGS fallback
  ///     moves the modes; fallback_sweeps = 20 (doubling from there) moves them in fewer rounds;
  ///   * a factorisation per direction (stale_factor_iterations = 0): on the granular files
  ///     thousands of sliding rows are coupled and the line search's damping retries change ρ
  ///     by 100-fold, so GMRES with a kept factor mostly fails to meet its tolerance and the
  ///     attempt costs more than the factorisation it would save.
  ProximalPointDef dual_finish_route = [] {
    ProximalPointDef d;
    d.initial_shift = 1e-6;
    d.min_shift = 1e-7;
    d.inner_forcing = 0.1;
    d.newton_sparse.krylov_forcing = 1e-2;
    d.newton_sparse.krylov_max = 30;
    d.newton_sparse.fallback_sweeps = 20;
    d.newton_sparse.stale_factor_iterations = 0;
    d.newton_sparse.lane_dot = true;
    d.max_stalls = 0;
    return d;
  }();

  /// After the proximal finish, when the target is still not reached: the pivoting finish
  /// (pivot_finish.hpp: the contact problem as a standard LCP by Lemke's method, then the
  /// newton-sparse finish from its answer) on problems whose split LCP (normal rows + 3 per
  /// friction row) has at most this many unknowns (default 1200: its dense tableau is O(N²)
  /// memory and work per pivot; 0 = none).
  int pivot_rows = 1200;

  /// After the safeguard, when the target is still not reached: the local pivoting finish
  /// (pivot_finish.hpp, local_pivot_solve). The contacts with a row whose natural-map residual
  /// exceeds local_pivot_threshold times the best iterate's (the rows whose modes block Newton:
  /// closed contacts that should open, sticking rows that should slide) and `local_pivot_rings`
  /// rings of the contacts coupled to them through A make a subproblem with the other rows
  /// fixed at the best iterate; Lemke solves it, 30 newton-sparse iterations (their own count,
  /// outside options.max_sweeps) polish the whole problem from there; at most
  /// local_pivot_rounds rounds, each from the best iterate, ending at the first that does not
  /// lower the best residual. A ring is added only while the subproblem's split LCP has at most local_pivot_rows unknowns
  /// (the last ring in part, most-coupled contacts first; the dense tableau costs O(N²) memory
  /// and work per pivot). 0 = no local finish (the default: opt-in).
  int local_pivot_rows = 0;
  int local_pivot_rings = 2;           ///< rings of coupled contacts around the violators
  double local_pivot_threshold = 0.9;  ///< violator: row residual above this × the worst row's
  int local_pivot_rounds = 3;          ///< rounds at most
  double local_pivot_shift = 0.0;      ///< proximal δ of the subproblem, relative to max A_ii

  /// Last, when the target is still not reached on a problem with friction: continuation in μ
  /// (finish/mu_continuation.hpp). Whole prox-newton solves (this definition, continuation off;
  /// to the target, options.max_sweeps each, no checkpoints) of the problem with every μ scaled
  /// by t_k = 1 − (1 − continuation_first)·2^−k, k = 0 … continuation_stages − 1, the first
  /// from the guess and each from the last one's answer, then of the problem itself from the
  /// last, ending at the first solve that misses its target. On resting piles where every
  /// local route stops on a plateau of near-solutions a few
  /// R above the target, the stages follow a branch of solutions from the nearly frictionless
  /// problem to one of the problem itself (docs/solvers.md "Impact steps that stop a few R
  /// short"). Only solves that missed the target pay for it. 0 = none.
  int continuation_stages = 7;
  double continuation_first = 0.25;  ///< t_0, the fraction of μ of the first stage, in (0, 1)
  /// The continuation runs only when the best hard residual of the other parts is at most this
  /// multiple of the target (≥ 1; infinity: whenever they miss it). It is the remedy for a
  /// plateau of near-solutions a few R short; a solve that ends far above its target (a target
  /// the problem's conditioning puts out of reach, as the solution test on a deep settled pile)
  /// would pay up to continuation_stages + 1 further whole solves for nothing.
  double continuation_within = 10.0;
};

/// Work of one solve.
struct ProxNewtonStats {
  int lead_sweeps = 0;      ///< nncg sweeps of the lead stage
  int drift_jumps = 0;      ///< drift jumps of the lead stage (degenerate_drift_jumps)
  int outer = 0;            ///< outer passes
  int newton = 0;           ///< Newton iterations in subproblems
  int finish_newton = 0;    ///< newton-sparse iterations of the finishes (both kinds)
  int proximal_finish_newton = 0;  ///< of those, in the proximal-point finish
  int safeguard_sweeps = 0; ///< nncg sweeps of the safeguard
  int factorizations = 0;   ///< numeric factorisations (subproblems and both finishes)
  int analyses = 0;         ///< symbolic analyses
  int line_search_steps = 0;  ///< 1D Newton steps (body) or merit trials (dual) in line searches
  int full_steps = 0;       ///< body space, coupled bounds: Newton steps taken whole
  int krylov = 0;           ///< body space, coupled bounds: GMRES iterations of the directions
  int cg = 0;               ///< body space: CG iterations with a kept factor (stale_factor_iterations)
  int pivots = 0;           ///< Lemke pivots of the pivoting finish
  int continuation_solves = 0;  ///< prox-newton solves of the continuation in μ (their work in the counts above)
};

class ProxNewtonSolver final : public LcpSolver {
 public:
  explicit ProxNewtonSolver(const ProxNewtonDef& def = {});
  ~ProxNewtonSolver() override;
  [[nodiscard]] std::string name() const override { return "prox-newton"; }
  // needs_assembled_matrix() stays true: the dual form and the newton-sparse finish read A
  // (body space does not; handed a problem without A, the finish forms it for that solve).
  [[nodiscard]] SolveResult solve(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& options) override;
  /// Statistics of the last solve of this object.
  [[nodiscard]] ProxNewtonStats last_stats() const;
  /// Called from options.on_checkpoint during a solve: the work up to the iterate that
  /// checkpoint sees (last_stats()'s counts so far, the part in progress included: the lead
  /// sweeps, a finish's Newton iterations and factorisations). The bench counts the
  /// factorisations to its accuracy R with it.
  [[nodiscard]] ProxNewtonStats checkpoint_stats() const;

 private:
  struct State;  // factorisations kept across solves, the last statistics
  ProxNewtonDef def_;
  std::unique_ptr<State> state_;
};

std::unique_ptr<LcpSolver> make_prox_newton(const ProxNewtonDef& def = {});

}  // namespace dc
