#pragma once
// The oracle λ*: this step's LCP solved to tight tolerance. It is the "copy" warm start
// (an upper bound on what any predictor can achieve) and the teacher of sph/cnn.
#include <Eigen/Core>
#include <string>

#include "dc/engine/lcp_problem.hpp"
#include "dc/engine/lcp_solver.hpp"

namespace dc {

struct OracleOptions {
  std::string solver = "newton";  ///< exact/Newton-type method tried first
  double tolerance = 1e-9;        ///< natural-map residual accepted from it [N], relative to max(1, ‖λ‖∞)
  int polish_sweeps = 20000;      ///< PGS sweeps of the fallback/polish stage
  double polish_theta = 1e-12;    ///< PGS stopping θ of the fallback [N]
};

struct OracleSolution {
  Eigen::VectorXd lambda;
  double residual = 0;     ///< natural-map residual of lambda [N]
  std::string method;      ///< which stage produced it ("newton", "newton+pgs", "pgs")
  bool accurate = false;   ///< residual within tolerance
};

/// Solves `p` tightly: the Newton-type method first (from `guess` if given), then a
/// matrix-free PGS polish from its result when the residual is not yet within tolerance.
OracleSolution solve_oracle(const LcpProblem& p, const Eigen::VectorXd* guess = nullptr,
                            const OracleOptions& options = {});

}  // namespace dc
