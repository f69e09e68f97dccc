#pragma once
// The oracle λ*: this step's LCP solved to tight tolerance. It is the "copy" warm start
// (an upper bound on what any predictor can achieve) and the teacher of sph/cnn.
#include <Eigen/Core>
#include <string>

#include "dc/engine/lcp_problem.hpp"
#include "dc/engine/lcp_solver.hpp"

namespace dc {

struct OracleOptions {
  std::string solver = "newton";  ///< exact/Newton-type method of stage 2
  double tolerance = 1e-9;        ///< natural-map residual accepted [N], relative to max(1, ‖λ‖∞)
  int polish_sweeps = 20000;      ///< PGS sweep cap of stage 1
  double polish_theta = 1e-11;    ///< PGS stopping θ of stage 1 [N]
};

struct OracleSolution {
  Eigen::VectorXd lambda;
  double residual = 0;     ///< natural-map residual of lambda [N]
  std::string method;      ///< which stage produced it ("pgs", "pgs+newton", "empty")
  bool accurate = false;   ///< residual within tolerance
};

/// Solves `p` tightly: stage 1 is matrix-free PGS from `guess` (zeros if null) until
/// θ ≤ polish_theta; when its natural residual is not within tolerance, stage 2 runs the
/// Newton-type method from that iterate and the more accurate of the two is returned.
OracleSolution solve_oracle(const LcpProblem& p, const Eigen::VectorXd* guess = nullptr,
                            const OracleOptions& options = {});

}  // namespace dc
