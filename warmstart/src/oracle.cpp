#include "dc/warmstart/oracle.hpp"

#include <algorithm>
#include <cmath>

namespace dc {
namespace {

/// Stages 2 and 3 stop at this fraction of the residual the oracle accepts.
constexpr double kStopMargin = 0.5;

}  // namespace

OracleSolution solve_oracle(const LcpProblem& p, const Eigen::VectorXd* guess,
                            const OracleOptions& o) {
  OracleSolution out;
  const int n = p.rows();
  if (n == 0) {
    out.lambda.resize(0);
    out.method = "empty";
    out.accurate = true;
    return out;
  }
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd& start = guess && guess->size() == n && guess->allFinite() ? *guess : zero;
  auto good = [&](const Eigen::VectorXd& l, double res) {
    return res <= o.tolerance * std::max(1.0, l.cwiseAbs().maxCoeff());
  };

  // Stage 1: the iterative solver from the guess to a tight θ ("" = none: stage 2 starts from
  // the guess).
  if (o.iterative.empty()) {
    out.lambda = start;
    out.method = "guess";
  } else {
    SolverOptions po;
    po.record_theta = false;
    po.max_sweeps = o.polish_sweeps;
    po.tolerance = o.polish_theta;
    const SolveResult q = make_solver(o.iterative)->solve(p, start, po);
    out.lambda = q.lambda.size() == n && q.lambda.allFinite() ? q.lambda : start;
    out.method = o.iterative;
  }
  out.residual = natural_residual(p, out.lambda);
  // Stages 2 and 3: Newton-type methods from the most accurate iterate; each result is kept
  // only if it is more accurate.
  for (const std::string* name : {&o.solver, &o.fallback_solver}) {
    if (name->empty() || good(out.lambda, out.residual)) break;
    SolverOptions so;
    so.record_theta = false;
    so.exact_tolerance = o.tolerance;
    // Stop where the oracle's own test accepts (residual [N] ≤ tolerance·max(1, ‖λ‖∞)), with a
    // margin for the change of ‖λ‖∞ on the way, rather than at the methods' solution target
    // tolerance·‖b‖∞, which is far tighter when ‖λ‖∞ ≫ ‖b‖∞ and sends prox-newton to its
    // pivoting finish for accuracy nobody asked for.
    if (o.stop_when_accepted)
      so.tolerance = kStopMargin * o.tolerance * std::max(1.0, out.lambda.cwiseAbs().maxCoeff());
    if (name == &o.solver && o.solver_iterations > 0) so.max_sweeps = o.solver_iterations;
    const SolveResult r = make_solver(*name)->solve(p, out.lambda, so);
    if (r.lambda.size() != n || !r.lambda.allFinite()) continue;
    const double res = natural_residual(p, r.lambda);
    if (res < out.residual) {
      out.lambda = r.lambda;
      out.residual = res;
      out.method += "+" + *name;
    }
  }
  out.accurate = good(out.lambda, out.residual);
  return out;
}

}  // namespace dc
