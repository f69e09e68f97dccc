#pragma once
// The route `deepcontact lcp solve FILE` takes when no solver is named (docs/lcp.md "The
// default route"): chosen by the kind of problem, so that every problem file the project
// reads is solved without options.
//   * a standard LCP (every row lo = 0, hi = +∞, no friction): `lemke` (exact pivoting; it
//     also proves infeasibility);
//   * anything else (box bounds, friction rows: a 2D frictional-contact problem): the plain
//     semismooth Newton `newton-sparse` to the solution test, at most `plain_iterations`
//     iterations (where it converges it needs few); when it does not pass the solution test
//     (it stalls on singular or slightly indefinite W, e.g. Siconos' granular files),
//     `prox-newton` from λ = 0 (prox_newton.hpp: convex frozen-friction passes and a proximal
//     finish); when that fails too, the proximal-point route around newton-sparse
//     (proximal_point.hpp) from λ = 0. The first answer that passes the solution test is
//     returned, else the one with the smallest natural residual.
#include <string>

#include "dc/lcp/lcp_solver.hpp"

namespace dc {

struct DefaultRouteDef {
  /// Iteration limit of the plain newton-sparse run before prox-newton takes over (default
  /// 30: where the plain run converges it needs a few to a few tens of iterations; where it
  /// stalls each further iteration costs a factorisation and gains little).
  int plain_iterations = 30;
  /// false: skip the plain run and start with prox-newton (frictional problems only; a
  /// standard LCP is then solved by the proximal route around lemke).
  bool plain = true;
  /// false: never go past the plain run.
  bool proximal = true;
};

/// What the default route did.
struct RouteResult {
  SolveResult result;  ///< the answer returned (status, λ, residual of the solver that gave it)
  std::string solver;  ///< the solver whose answer `result` is: "lemke", "newton-sparse", "prox-newton", "proximal:newton-sparse"
  std::string route;   ///< the solvers run, in order, joined by " then " (e.g. "newton-sparse then prox-newton")
};

/// true when every row of `p` is a standard LCP row (lo = 0, hi = +∞, no friction).
bool is_standard_lcp(const LcpProblem& p);

/// Solves `problem` by the default route above, from λ = 0. `options.exact_tolerance` sets the
/// solution test; `options.max_sweeps` caps the plain run as well (the smaller of it and
/// def.plain_iterations); the other fields are unused (every solver runs to the solution test).
/// `sweeps` of the result counts the iterations (pivots) of every solver run.
RouteResult solve_with_default_route(const LcpProblem& problem, const SolverOptions& options = {},
                                     const DefaultRouteDef& def = {});

}  // namespace dc
