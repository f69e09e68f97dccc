#pragma once
// The oracle λ*: this step's LCP solved to tight tolerance. It is the "copy" warm start
// (an upper bound on what any predictor can achieve) and the teacher of sph/cnn.
#include <Eigen/Core>
#include <string>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace dc {

/// The oracle's route: an iterative stage from the guess, then Newton-type polishing only where
/// the iterate is not yet accurate. The defaults (nncg ≤ 2000 sweeps to θ ≤ 1e-5 N, then at most
/// 10 newton-sparse iterations, then prox-newton, each stopping once the oracle accepts) are the
/// fastest accurate route of those benchmarks/micro/micro_oracle.cpp compares on the seed
/// scene's steps and through the impact (docs/solvers.md "The oracle").
struct OracleOptions {
  /// Stage 1: iterative solver from the guess until θ ≤ polish_theta or polish_sweeps ("" = no
  /// stage 1: stage 2 starts from the guess). From the previous step's λ* most steps end here;
  /// on the others the cap hands over to stage 2 early rather than sweeping on. θ is a stop, not
  /// the accuracy: the natural residual decides whether stage 2 runs, and a Newton iteration
  /// from a λ near the solution gains more than the last sweeps to a tiny θ.
  std::string iterative = "nncg";
  int polish_sweeps = 2000;       ///< sweep cap of stage 1
  double polish_theta = 1e-5;     ///< stopping θ of stage 1 [N]
  /// Stage 2 (when stage 1 is not accurate): a Newton-type method from stage 1's iterate.
  /// newton-sparse converges in a few iterations where its modes are right; where they are
  /// not, its line search stalls, so it is capped and hands over.
  std::string solver = "newton-sparse";
  /// Iteration cap of stage 2 (0 = SolverOptions' default).
  int solver_iterations = 10;
  /// Stage 3 (when stage 2 is not accurate either): another method from the better iterate
  /// ("" = none). prox-newton solves only convex subproblems on the way and reaches the
  /// tolerance on the steps where newton-sparse stalls.
  std::string fallback_solver = "prox-newton";
  double tolerance = 1e-9;        ///< natural-map residual accepted [N], relative to max(1, ‖λ‖∞)
  /// Stages 2 and 3 stop once their residual is half the accepted one (true), or run to their
  /// own solution test tolerance·‖b‖∞ (false: on piles, where ‖λ‖∞ [N] is hundreds of times
  /// ‖b‖∞ [m/s], a far tighter residual than the oracle accepts).
  bool stop_when_accepted = true;
};

struct OracleSolution {
  Eigen::VectorXd lambda;
  double residual = 0;     ///< natural-map residual of lambda [N]
  std::string method;      ///< the stages that produced it ("nncg", "nncg+newton-sparse", "empty", …)
  bool accurate = false;   ///< residual within tolerance
};

/// Solves `p` tightly: stage 1 is the iterative solver from `guess` (zeros if null or not finite)
/// until θ ≤ polish_theta (none when `iterative` is empty: method "guess…"); while the natural residual is not within tolerance, stage 2 and then
/// stage 3 run from the most accurate iterate so far, and the most accurate one is returned.
OracleSolution solve_oracle(const LcpProblem& p, const Eigen::VectorXd* guess = nullptr,
                            const OracleOptions& options = {});

}  // namespace dc
