#include "dc/cnn/data_set_oracle_solver.hpp"

namespace dc {

DataSetOracleSolver::DataSetOracleSolver(const DataSetOracle& oracle)
    : method_(oracle.method), pgs_(make_solver("pgs")) {
  pgs_options_.max_sweeps = oracle.sweeps;
  pgs_options_.tolerance = oracle.tolerance;
  pgs_options_.record_theta = false;
  oracle_options_.tolerance = oracle.tolerance;
  oracle_options_.polish_sweeps = oracle.sweeps;
}

OracleStep DataSetOracleSolver::solve(const LcpProblem& problem, const Eigen::VectorXd& guess) const {
  OracleStep out;
  if (method_ == OracleKind::Pgs) {
    SolveResult r = pgs_->solve(problem, guess, pgs_options_);
    out.lambda = std::move(r.lambda);
    out.residual = r.residual;
  } else {
    OracleSolution o = solve_oracle(problem, &guess, oracle_options_);
    out.lambda = std::move(o.lambda);
    out.residual = o.residual;
  }
  return out;
}

}  // namespace dc
