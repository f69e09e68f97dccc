#pragma once
// prox-newton's lead stage (ProxNewtonDef::lead_sweeps, lead_sweep): one nncg (or nncg-colored)
// run from the guess, looked at every kLeadChunk sweeps, where its iterate goes to the caller
// (the best-iterate bookkeeping) and the window rule (LeadRate) decides whether the run goes on.
// The momentum and Δu carry on across the looks, so the stage makes the sweeps plain nncg (or
// nncg-colored) makes to the same sweep.
#include <Eigen/Core>
#include <functional>

#include "dc/lcp/lcp_solver.hpp"

namespace dc::solvers::prox {

/// Sweeps between looks at the hard residual.
inline constexpr int kLeadChunk = 50;

struct LeadStageDef {
  int cap = 0;          ///< sweeps at most (> 0)
  int window = 0;       ///< LeadRate's window [looks] (0: the rate rule)
  double gain = 2.0;    ///< LeadRate's fall asked over a window
  int stall = 0;        ///< LeadRate's stall rule [looks without a new best] (0: none)
  double start = 0.0;   ///< hard residual at the guess [N]
  double target = 0.0;  ///< hard residual that ends the stage [N]
  /// The nncg-colored solver that sweeps (solvers::nncg_colored_solve), or null: nncg's
  /// natural-order sweep (nncg_solve). The same hook either way.
  LcpSolver* colored = nullptr;
  /// Called at every look after `consider`, with the sweeps so far (null: none); true ends the
  /// stage (prox-newton's probes, ProxNewtonDef::probe_sweeps). The run's momentum is untouched.
  std::function<bool(int sweeps)> probe;
  /// Drift jumps at most (drift_jump.hpp; 0: none): at a look where the changes over the last
  /// two chunks agree to `drift_linearity`, λ jumps to where the drift meets the first bound and
  /// a fresh nncg run goes on from there (its momentum restarted, as the drift had it anyway).
  int drift_jumps = 0;
  double drift_linearity = 0.1;
};

/// The best hard residual [N] so far after the caller took λ into account.
using LeadConsider = std::function<double(const Eigen::VectorXd& lambda)>;

/// Runs the stage from λ. `options` carries the caller's checkpoints (numbered from the stage's
/// first sweep); its max_sweeps, tolerance and record_theta are set here. Every look, and the
/// last iterate when the run ended between looks, goes through `consider`. Returns the sweeps
/// made (at least 1, as a run that broke down in its first sweep still cost one). With `fall`,
/// LeadRate::window_fall() at the end is written there; with `jumps`, the drift jumps made.
int run_lead_stage(const LcpProblem& p, const Eigen::VectorXd& lambda, const LeadStageDef& def, SolverOptions options,
                   const LeadConsider& consider, double* fall = nullptr, int* jumps = nullptr);

}  // namespace dc::solvers::prox
