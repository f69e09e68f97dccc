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
  const Eigen::VectorXd& start = guess && guess->size() == n && guess->allFinite() ? *guess : zero;
  auto good = [&](const Eigen::VectorXd& l, double res) {
    return res <= o.tolerance * std::max(1.0, l.cwiseAbs().maxCoeff());
  };

  // Stage 1: PGS from the guess to a tight θ. From a good guess (the previous step's λ*
  // matched by key) this is the cheapest accurate solve on contact piles (~ms), and it
  // always makes progress.
  SolverOptions po;
  po.record_theta = false;
  po.max_sweeps = o.polish_sweeps;
  po.tolerance = o.polish_theta;
  const auto pgs = make_solver(p.has_jacobian() ? "pgs" : "pgs-assembled");
  const SolveResult q = pgs->solve(p, start, po);
  out.lambda = q.lambda.size() == n && q.lambda.allFinite() ? q.lambda : start;
  out.residual = natural_residual(p, out.lambda);
  out.method = "pgs";
  if (good(out.lambda, out.residual)) {
    out.accurate = true;
    return out;
  }
  // Stage 2: the Newton-type method from the PGS result; keep whichever is more accurate.
  SolverOptions so;
  so.record_theta = false;
  so.exact_tolerance = o.tolerance;
  const SolveResult r = make_solver(o.solver)->solve(p, out.lambda, so);
  if (r.lambda.size() == n && r.lambda.allFinite()) {
    const double res = natural_residual(p, r.lambda);
    if (res < out.residual) {
      out.lambda = r.lambda;
      out.residual = res;
      out.method = "pgs+" + o.solver;
    }
  }
  out.accurate = good(out.lambda, out.residual);
  return out;
}

}  // namespace dc
