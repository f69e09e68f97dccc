#include "dc/warmstart/oracle.hpp"

#include <cmath>

namespace dc {

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
  const Eigen::VectorXd& start = guess && guess->size() == n ? *guess : zero;

  SolverOptions so;
  so.record_theta = false;
  so.exact_tolerance = o.tolerance;
  const auto exact = make_solver(o.solver);
  SolveResult r = exact->solve(p, start, so);
  out.lambda = r.lambda.size() == n && r.lambda.allFinite() ? r.lambda : start;
  out.residual = natural_residual(p, out.lambda);
  out.method = o.solver;
  auto good = [&](double res) { return res <= o.tolerance * std::max(1.0, out.lambda.cwiseAbs().maxCoeff()); };
  if (good(out.residual)) {
    out.accurate = true;
    return out;
  }
  // Polish (or replace) with PGS, which always makes progress on these problems.
  SolverOptions po;
  po.record_theta = false;
  po.max_sweeps = o.polish_sweeps;
  po.tolerance = o.polish_theta;
  const auto pgs = make_solver(p.has_jacobian() ? "pgs" : "pgs-assembled");
  SolveResult q = pgs->solve(p, out.lambda, po);
  if (q.lambda.allFinite() && q.residual < out.residual) {
    out.lambda = q.lambda;
    out.residual = q.residual;
    out.method = o.solver + "+pgs";
  }
  out.accurate = good(out.residual);
  return out;
}

}  // namespace dc
