// The default route of `lcp solve` (dc/lcp/default_route.hpp).
#include "dc/lcp/default_route.hpp"

#include <algorithm>

#include "dc/lcp/proximal_point.hpp"
#include "solvers/solver_common.hpp"

namespace dc {

bool is_standard_lcp(const LcpProblem& p) { return solvers::first_nonstandard_row(p) < 0; }

namespace {

SolverId solver(SolverKind kind) {
  SolverId id;
  id.kind = kind;
  return id;
}

SolverOptions exact_options(const SolverOptions& given) {
  SolverOptions o;
  o.exact_tolerance = given.exact_tolerance;
  o.record_theta = false;
  o.tolerance = 0.0;  // to the solution test
  return o;
}

RouteResult solve_lcp(const LcpProblem& problem, const SolverOptions& given, const DefaultRouteDef& def) {
  SolverOptions o = given;
  o.record_theta = false;
  if (!def.plain) {
    ProximalPointDef pd;
    pd.inner_solver = solver(SolverKind::Lemke);
    return {solve_proximal_point(problem, Eigen::VectorXd(), o, pd), "proximal:lemke", "proximal:lemke"};
  }
  return {make_solver(solver(SolverKind::Lemke))->solve(problem, Eigen::VectorXd(), o), "lemke", "lemke"};
}

}  // namespace

RouteResult solve_with_default_route(const LcpProblem& problem, const SolverOptions& options,
                                     const DefaultRouteDef& def) {
  if (is_standard_lcp(problem)) return solve_lcp(problem, options, def);
  const SolverOptions exact = exact_options(options);
  RouteResult out;
  int sweeps = 0;
  if (def.plain) {
    SolverOptions o = exact;
    o.max_sweeps = std::max(0, std::min(options.max_sweeps, def.plain_iterations));
    out.result = make_solver(solver(SolverKind::NewtonSparse))->solve(problem, Eigen::VectorXd(), o);
    out.solver = out.route = "newton-sparse";
    sweeps = out.result.sweeps;
    // Converged, or refused (an invalid problem the proximal route would refuse too).
    if (out.result.status == SolveStatus::Converged || out.result.status == SolveStatus::InvalidInput ||
        !def.proximal)
      return out;
  }
  // From λ = 0, not from the plain run's best iterate: a stalled Newton iterate of an
  // indefinite W is a poor start for the shifted problems (they then hit their outer limit).
  SolveResult prox = solve_proximal_point(problem, Eigen::VectorXd(), exact, ProximalPointDef{});
  sweeps += prox.sweeps;
  out.route += out.route.empty() ? "proximal:newton-sparse" : " then proximal:newton-sparse";
  const bool better = !def.plain || prox.status == SolveStatus::Converged || !(out.result.residual <= prox.residual);
  const std::string plain_note =
      def.plain ? "newton-sparse: " + std::string(to_string(out.result.status)) + " (" + out.result.message + "); " : "";
  if (better) {
    out.result = std::move(prox);
    out.solver = "proximal:newton-sparse";
  }
  out.result.message = plain_note + "proximal:newton-sparse: " + (better ? out.result.message : prox.message);
  out.result.sweeps = sweeps;
  return out;
}

}  // namespace dc
