#include "solvers/prox_newton/lead/lead_stage.hpp"

#include <algorithm>

#include "solvers/prox_newton/lead/lead_rate.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers::prox {

int run_lead_stage(const LcpProblem& p, const Eigen::VectorXd& lambda, const LeadStageDef& def, SolverOptions options,
                   const LeadConsider& consider, double* fall) {
  options.record_theta = false;
  options.tolerance = 0.0;
  options.max_sweeps = def.cap;
  LeadRate rate(def.start, def.window, def.gain, def.stall);
  int looked = 0;  // sweeps at the last look
  SweepWatch watch;
  watch.every = kLeadChunk;
  watch.stop = [&](int sweeps, const Eigen::VectorXd& x) {
    looked = sweeps;
    const double best = consider(x);
    if (def.probe && def.probe(sweeps)) return true;
    return !rate.go_on(best, def.target, sweeps, kLeadChunk, def.cap);
  };
  const SolveResult r = def.colored != nullptr ? nncg_colored_solve(*def.colored, p, lambda, options, &watch)
                                               : nncg_solve(p, lambda, options, &watch);
  // A run that ended between looks (the cap, a non-finite sweep): its last finite iterate.
  if (r.sweeps != looked && r.lambda.size() == p.rows() && r.lambda.allFinite()) consider(r.lambda);
  if (fall) *fall = rate.window_fall();
  return std::max(r.sweeps, 1);
}

}  // namespace dc::solvers::prox
