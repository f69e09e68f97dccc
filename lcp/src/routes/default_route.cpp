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

namespace {

/// The stages of the frictional route, run in order; the answer kept is the first that passes
/// the solution test, else the one with the smallest natural residual.
class Stages {
 public:
  void add(SolveResult next, const std::string& name) {
    out_.route += (out_.route.empty() ? "" : " then ") + name;
    sweeps_ += next.sweeps;
    const std::string summary = name + ": " + to_string(next.status) + " (" + next.message + ")";
    const bool first = history_.empty();
    history_ += (first ? "" : "; ") + summary;
    if (first || next.status == SolveStatus::Converged || !(out_.result.residual <= next.residual)) {
      out_.result = std::move(next);
      out_.solver = name;
    }
    // One stage: its own message; several: what each said, in order.
    if (!first) out_.result.message = history_;
    out_.result.sweeps = sweeps_;
  }
  /// Converged, or refused (an invalid problem every later stage refuses too).
  [[nodiscard]] bool settled() const {
    return out_.result.status == SolveStatus::Converged || out_.result.status == SolveStatus::InvalidInput;
  }
  [[nodiscard]] bool empty() const { return history_.empty(); }
  RouteResult take() { return std::move(out_); }

 private:
  RouteResult out_;
  std::string history_;
  int sweeps_ = 0;
};

}  // namespace

RouteResult solve_with_default_route(const LcpProblem& problem, const SolverOptions& options,
                                     const DefaultRouteDef& def) {
  if (is_standard_lcp(problem)) return solve_lcp(problem, options, def);
  const SolverOptions exact = exact_options(options);
  Stages stages;
  // prox-newton from λ = 0: convex frozen-friction passes, then its finishes.
  SolverOptions first = exact;
  first.max_sweeps = std::max(0, options.max_sweeps);
  stages.add(make_solver(solver(SolverKind::ProxNewton))->solve(problem, Eigen::VectorXd(), first), "prox-newton");
  if (stages.settled() || !def.proximal) return stages.take();
  if (def.plain) {
    SolverOptions o = exact;
    o.max_sweeps = std::max(0, std::min(options.max_sweeps, def.plain_iterations));
    stages.add(make_solver(solver(SolverKind::NewtonSparse))->solve(problem, Eigen::VectorXd(), o), "newton-sparse");
    if (stages.settled()) return stages.take();
  }
  // The proximal-point route around newton-sparse from λ = 0, not from a stalled iterate: a
  // stalled Newton iterate of an indefinite W is a poor start for the shifted problems.
  stages.add(solve_proximal_point(problem, Eigen::VectorXd(), exact, ProximalPointDef{}), "proximal:newton-sparse");
  return stages.take();
}

}  // namespace dc
