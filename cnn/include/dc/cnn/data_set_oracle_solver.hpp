#pragma once
// λ* of one step as a data set's oracle prescribes (DataSetOracle, data_set.hpp): the one
// place that turns the stored oracle attributes into a solve, so that data generation and
// every later replay of a data set's trajectory (the PGS-loss samples of research) solve
// alike and follow the same trajectory.
#include <Eigen/Core>
#include <memory>

#include "dc/cnn/data_set.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/warmstart/oracle.hpp"

namespace dc {

/// One step's oracle solution.
struct OracleStep {
  Eigen::VectorXd lambda;  ///< λ* [N] in the problem's row order
  double residual = 0;     ///< pgs: the solver's final residual; newton: solve_oracle's residual
};

class DataSetOracleSolver {
 public:
  /// `oracle` must be valid (DataSetOracle::validate).
  explicit DataSetOracleSolver(const DataSetOracle& oracle);
  /// λ* of `problem` from `guess` (the builtin warm start: it only makes the tight solve
  /// cheaper). pgs: matrix-free PGS until θ ≤ tolerance or `sweeps` sweeps, θ not recorded;
  /// newton: solve_oracle with the tolerance and `sweeps` polish sweeps.
  [[nodiscard]] OracleStep solve(const LcpProblem& problem, const Eigen::VectorXd& guess) const;

 private:
  OracleKind method_;
  std::unique_ptr<LcpSolver> pgs_;
  SolverOptions pgs_options_;
  OracleOptions oracle_options_;
};

}  // namespace dc
