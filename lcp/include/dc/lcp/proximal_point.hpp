#pragma once
// The proximal-point route: an exact solver (newton-sparse) on a sequence of shifted problems,
// for assembled LCPs whose A is singular or slightly indefinite (e.g. Siconos' granular 2D files,
// W printed with `%g`; docs/lcp.md "Singular and indefinite W"). Outer iteration k solves, from λ_k,
//     w = (A + δ_k I) λ + (b − δ_k λ_k),   same bounds and friction coupling;
// a fixed point solves the original LCP, and A + δI is positive definite when δ exceeds the most
// negative eigenvalue of A. δ shrinks `shrink`-fold after a converged inner solve and grows by the
// same factor (restarting from the best iterate) after one that did not converge; it never
// shrinks below a shift that failed (that floor falls floor_decay-fold per converged inner
// solve). It stops when the natural residual of the ORIGINAL problem
// at the best iterate is ≤ target (options.tolerance [N] when > 0, else solution_target; checked
// after every inner iteration with stop_at_target): then
// Converged when that λ passes the solution test (solution_target), else ToleranceReached;
// SweepLimit after max_outer outer iterations, or earlier by max_stalls, floor_stalls or progress_window; InvalidInput, with the inner solver's message,
// when the inner solver refuses the problem (lemke on friction rows). λ is the best iterate
// seen. `sweeps` counts inner iterations in all.
#include <functional>
#include <string>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"

namespace dc {

struct ProximalPointDef {
  /// First shift δ_0 relative to max_i A_ii (dimensionless, default 1e-6).
  double initial_shift = 1e-6;
  /// Smallest and largest shift relative to max_i A_ii (defaults 1e-8 and 1e-2).
  double min_shift = 1e-8;
  double max_shift = 1e-2;
  /// Factor δ shrinks by after a converged inner solve and grows by after a failed one (default 10).
  double shrink = 10.0;
  /// Outer iterations at most (default 200).
  int max_outer = 200;
  /// Stop after this many consecutive outer iterations without a new best residual (default 0:
  /// never; only max_outer stops the route).
  int max_stalls = 0;
  /// Factor the failure floor of δ (the largest shift whose inner solve failed) falls by after
  /// each converged inner solve, never below min_shift (default 1: a failed shift stays a floor
  /// for the rest of the route). Above 1, δ can fall again once passes succeed: the failure
  /// often belongs to row modes far from the solution, and a small δ converges faster near it.
  double floor_decay = 1.0;
  /// Failure floor of δ at the start, relative to max_i A_ii (default 0: min_shift); δ_0 is
  /// max(initial_shift, initial_floor). A caller that ran the route on the same problem before
  /// passes the floor that run ended with (ProximalPointStats::floor): the shifts below it
  /// failed there, and their inner solves fail again from a nearby start.
  double initial_floor = 0.0;
  /// Stop after this many consecutive outer iterations at a raised failure floor (δ at the
  /// floor, floor above min_shift) without a new best residual (default 0: never). There δ can
  /// neither fall nor rise, and passes without a new best repeat themselves; the message says
  /// the route stalled.
  int floor_stalls = 0;
  /// Stop when the best residual of the original problem fell less than progress_factor-fold
  /// over the last progress_window outer iterations (default 0: never). A caller with a cheaper
  /// fallback runs it sooner instead of spending max_outer slow passes.
  int progress_window = 0;
  /// Required fall of the best residual over progress_window outer iterations, as the ratio
  /// new/old (dimensionless, in (0, 1], default 0.5).
  double progress_factor = 0.5;
  /// When progress_window fires while δ's failure floor is above min_shift: the first time,
  /// reset that floor to min_shift, let δ shrink from there and restart the window instead of
  /// stopping (default false: stop).
  bool release_floor = false;
  /// Whether progress_window stops the route (default true). false: it never does; with
  /// release_floor it releases the failure floor each time it fires at a raised floor, and the
  /// route runs until the target or max_outer (a slow stretch at a raised floor costs outer
  /// iterations, never the steps that reach the target only late).
  bool window_stops = true;
  /// Stop an inner newton-sparse solve at its first iterate whose natural residual of the
  /// ORIGINAL problem is ≤ target, and return that iterate (default true). The inner solves aim
  /// at the shifted problem's own (tighter) target, and near the solution the original problem's
  /// residual can fall below the route's target many inner iterations before they get there.
  /// Costs one natural-residual evaluation of the original problem per inner iteration.
  bool stop_at_target = true;
  /// Called after every outer iteration with the route's numeric factorisations so far and its
  /// best residual of the original problem [N]; true stops the route there (default none: the
  /// route's own stops alone). A caller that runs the route as one part of a larger solve
  /// stops it by its own work budget; the route returns its best iterate as after any stop.
  std::function<bool(int factorizations, double best_residual)> stop_after;
  /// Iteration limit of each inner solve (default 200: the first, cold one needs most).
  int inner_iterations = 200;
  /// Inexact proximal point: each inner solve stops at max(inner target, inner_forcing × the
  /// best residual of the original problem so far) [N] (dimensionless, default 0: every inner
  /// solve to the inner target). Far from the solution the shift term δ(λ − λ_k) dominates the
  /// original problem's residual, and solving the shifted problem past a fraction of it does
  /// not move the next centre further.
  double inner_forcing = 0.0;
  /// The inner solver (default newton-sparse; any solver make_solver makes that reaches
  /// exact_tolerance on a positive definite problem).
  SolverId inner_solver{SolverKind::NewtonSparse};
  /// Settings of the inner solver when it is "newton-sparse": its defaults except exact GMRES
  /// directions (krylov_forcing = 0) — with the inexact default the warm-started inner solves
  /// of Siconos' 7002-contact file stalled above the exact tolerance.
  NewtonSparseDef newton_sparse = [] {
    NewtonSparseDef d;
    d.krylov_forcing = 0.0;
    return d;
  }();
};

/// Work of one route solve, summed over its inner solves (newton-sparse's counts; zero for
/// other inner solvers).
struct ProximalPointStats {
  int factorizations = 0;    ///< numeric factorisations
  int krylov_iterations = 0; ///< GMRES iterations
  double floor = 0.0;        ///< failure floor of δ at the end, relative to max_i A_ii
};

/// Solves `problem` by the proximal-point route above. The problem must carry A (a problem
/// with only J is assembled for this call). Throws InvalidArgument for an invalid def. With
/// `stats`, the route's work is written there.
SolveResult solve_proximal_point(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                 const SolverOptions& options, const ProximalPointDef& def = {},
                                 ProximalPointStats* stats = nullptr);

}  // namespace dc
