#pragma once
// The route `deepcontact lcp solve FILE` takes when no solver is named (docs/lcp.md "The
// default route"): chosen by the kind of problem, so that every problem file the project
// reads is solved without options.
//   * a standard LCP (every row lo = 0, hi = +∞, no friction): `lemke` (exact pivoting; it
//     also proves infeasibility);
//   * anything else (box bounds, friction rows: a 2D frictional-contact problem): `prox-newton`
//     from λ = 0 to the solution test (prox_newton.hpp: convex frozen-friction passes, a
//     newton-sparse finish once the row modes repeat, a proximal finish); when it does not pass
//     the solution test, the plain semismooth Newton `newton-sparse` from λ = 0, at most
//     `plain_iterations` iterations; when that fails too, the proximal-point route around
//     newton-sparse (proximal_point.hpp) from λ = 0. The first answer that passes the solution
//     test is returned, else the one with the smallest natural residual. prox-newton first:
//     where plain newton-sparse converges, prox-newton converges too, at little extra cost;
//     where newton-sparse stalls (singular or slightly indefinite W, e.g. Siconos' granular
//     files) its stalled iterations cost a factorisation each before anything else runs.
#include <string>

#include "dc/lcp/lcp_solver.hpp"

namespace dc {

struct DefaultRouteDef {
  /// Iteration limit of the plain newton-sparse run after prox-newton (default 30: where the
  /// plain run converges it needs a few to a few tens of iterations; where it stalls each
  /// further iteration costs a factorisation and gains little).
  int plain_iterations = 30;
  /// false: no plain newton-sparse run (frictional problems: prox-newton, then the
  /// proximal-point route; a standard LCP is then solved by the proximal route around lemke).
  bool plain = true;
  /// false: prox-newton alone (frictional problems), no later stage.
  bool proximal = true;
};

/// What the default route did.
struct RouteResult {
  SolveResult result;  ///< the answer returned (status, λ, residual of the solver that gave it)
  std::string solver;  ///< the solver whose answer `result` is: "lemke", "newton-sparse", "prox-newton", "proximal:newton-sparse"
  std::string route;   ///< the solvers run, in order, joined by " then " (e.g. "prox-newton then newton-sparse")
};

/// true when every row of `p` is a standard LCP row (lo = 0, hi = +∞, no friction).
bool is_standard_lcp(const LcpProblem& p);

/// Solves `problem` by the default route above, from λ = 0. `options.exact_tolerance` sets the
/// solution test; `options.max_sweeps` caps prox-newton's Newton iterations and the plain run
/// (the smaller of it and def.plain_iterations); the other fields are unused (every solver runs to the solution test).
/// `sweeps` of the result counts the iterations (pivots) of every solver run.
RouteResult solve_with_default_route(const LcpProblem& problem, const SolverOptions& options = {},
                                     const DefaultRouteDef& def = {});

}  // namespace dc
