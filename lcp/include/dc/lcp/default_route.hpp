#pragma once
// The route `deepcontact lcp solve FILE` takes when no solver is named (docs/lcp.md "The
// default route"): chosen by the kind of problem, so that every problem file the project
// reads is solved without options.
//   * a standard LCP (every row lo = 0, hi = +∞, no friction): `lemke` (exact pivoting; it
//     also proves infeasibility);
//   * anything else (box bounds, friction rows: a 2D frictional-contact problem): the plain
//     semismooth Newton `newton-sparse` to the solution test, at most `plain_iterations`
//     iterations; when it does not pass the solution test (it stalls on singular or slightly
//     indefinite W, e.g. Siconos' granular files), the proximal-point route around
//     newton-sparse (proximal_point.hpp) from λ = 0. The better of the two answers (smaller
//     natural residual) is returned.
#include <string>

#include "dc/lcp/lcp_solver.hpp"

namespace dc {

struct DefaultRouteDef {
  /// Iteration limit of the plain newton-sparse run before the proximal route takes over
  /// (default 100: where it converges it needs far fewer; where it stalls each further
  /// iteration costs time and gains little).
  int plain_iterations = 100;
  /// false: skip the plain run and go straight to the proximal route (frictional problems
  /// only; a standard LCP is solved by the proximal route around lemke).
  bool plain = true;
  /// false: never fall back to the proximal route.
  bool proximal = true;
};

/// What the default route did.
struct RouteResult {
  SolveResult result;  ///< the answer returned (status, λ, residual of the solver that gave it)
  std::string solver;  ///< the solver whose answer `result` is: "lemke", "newton-sparse", "proximal:newton-sparse"
  std::string route;   ///< the solvers run, in order, joined by " then " (e.g. "newton-sparse then proximal:newton-sparse")
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
