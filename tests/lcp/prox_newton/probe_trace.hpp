#pragma once
// What a prox-newton solve with checkpoints at every iteration shows of its probes: the lead
// sweeps after which a probe's Newton iterations began, and the lead's best hard residual at each
// of its looks. Shared by the probe tests (one probe, and later probes).
#include <algorithm>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"

namespace dc::test {

struct ProbeTrace {
  std::vector<int> probes;   // lead sweeps before each probe before the lead's last sweep
  std::vector<double> best;  // best[j]: the best hard residual after look j + 1 (the guess's included)
  SolveResult r;
  ProxNewtonStats st;
};

/// Solves p from zero with a checkpoint at every iteration; a look is every 50 lead sweeps (the
/// lead stage's chunk).
inline ProbeTrace probe_trace(const LcpProblem& p, const ProxNewtonDef& d, double tolerance, int max_sweeps) {
  constexpr int kLook = 50;
  SolverOptions o;
  o.max_sweeps = max_sweeps;
  o.tolerance = tolerance;
  for (int k = 1; k <= 3000; ++k) o.checkpoints.push_back(k);
  ProxNewtonSolver s(d);
  ProbeTrace out;
  double best = natural_residual(p, Eigen::VectorXd::Zero(p.rows()));
  int newton = 0;  // Newton iterations seen so far
  int sweeps = 0;  // lead sweeps seen so far
  o.on_checkpoint = [&](int, const Eigen::VectorXd& lambda) {
    const ProxNewtonStats at = s.checkpoint_stats();
    if (at.newton > newton) {  // a probe's (during the lead) or a later Newton part's iteration
      if (out.probes.empty() || out.probes.back() != sweeps) out.probes.push_back(sweeps);
      newton = at.newton;
    } else if (at.lead_sweeps > sweeps) {  // the lead's next sweep
      sweeps = at.lead_sweeps;
      best = std::min(best, natural_residual(p, lambda));
      if (sweeps % kLook == 0) out.best.push_back(best);
    }
  };
  out.r = s.solve(p, {}, o);
  out.st = s.last_stats();
  // Newton iterations after the lead's last sweep may be the Newton part's: only the probes
  // before it count.
  while (!out.probes.empty() && out.probes.back() >= out.st.lead_sweeps) out.probes.pop_back();
  return out;
}

}  // namespace dc::test
