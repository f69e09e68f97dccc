#include "solvers/prox_newton/lead/lead_stage.hpp"

#include <algorithm>
#include <array>
#include <vector>
#include <optional>

#include "solvers/prox_newton/lead/drift_jump.hpp"
#include "solvers/prox_newton/lead/lead_rate.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers::prox {
namespace {

/// The options of a run that starts after `done` sweeps of the stage: the caller's checkpoints
/// still ahead, numbered from the run's first sweep and reported in the stage's numbering.
SolverOptions run_options(const SolverOptions& options, int done, int cap) {
  SolverOptions o = options;
  o.max_sweeps = cap - done;
  if (done == 0 || !options.on_checkpoint) return o;
  o.checkpoints.clear();
  for (const int k : options.checkpoints)
    if (k > done) o.checkpoints.push_back(k - done);
  o.on_checkpoint = [&options, done](int k, const Eigen::VectorXd& x) { options.on_checkpoint(k + done, x); };
  return o;
}

}  // namespace

int run_lead_stage(const LcpProblem& p, const Eigen::VectorXd& lambda, const LeadStageDef& def, SolverOptions options,
                   const LeadConsider& consider, double* fall, int* jumps_made) {
  options.record_theta = false;
  options.tolerance = 0.0;
  options.max_sweeps = def.cap;
  LeadRate rate(def.start, def.window, def.gain, def.stall);
  int done = 0;    // sweeps of the runs before the current one (a drift jump starts a new run)
  int looked = 0;  // sweeps at the last look
  int jumps = 0;
  std::array<Eigen::VectorXd, 2> recent;  // the iterates of the two sweeps before a look
  Eigen::VectorXd start = lambda;
  for (;;) {
    std::optional<Eigen::VectorXd> jumped;
    // Drift jumps look at every sweep, keeping the two iterates before each look (the sweep is in
    // natural order: nncg-colored would map λ back to row order at every look).
    const bool watch_drift = jumps < def.drift_jumps && def.colored == nullptr;
    SweepWatch watch;
    watch.every = watch_drift ? 1 : kLeadChunk;
    watch.stop = [&](int sweeps, const Eigen::VectorXd& x) {
      if (sweeps % kLeadChunk != 0) {
        if (sweeps % kLeadChunk >= kLeadChunk - 2) recent[static_cast<size_t>(sweeps % kLeadChunk - (kLeadChunk - 2))] = x;
        return false;
      }
      looked = done + sweeps;
      const double best = consider(x);
      if (def.probe && def.probe(looked)) return true;
      if (!rate.go_on(best, def.target, looked, kLeadChunk, def.cap)) return true;
      if (watch_drift && sweeps >= kLeadChunk) jumped = drift_jump(p, recent[0], recent[1], x, def.drift_linearity);
      return jumped.has_value();
    };
    // The first run takes the stage's options as they are (no copy of a long checkpoint list).
    SolverOptions shifted;
    if (done > 0) shifted = run_options(options, done, def.cap);
    const SolverOptions& o = done > 0 ? shifted : options;
    const SolveResult r = def.colored != nullptr ? nncg_colored_solve(*def.colored, p, start, o, &watch)
                                                 : nncg_solve(p, start, o, &watch);
    if (jumped) {
      // A new run from the jumped iterate, which the caller sees as a look's.
      ++jumps;
      done = looked;
      start = std::move(*jumped);
      if (jumps_made) *jumps_made = jumps;
      if (consider(start) > def.target) continue;
      if (fall) *fall = rate.window_fall();
      return done;
    }
    // A run that ended between looks (the cap, a non-finite sweep): its last finite iterate.
    if (done + r.sweeps != looked && r.lambda.size() == p.rows() && r.lambda.allFinite()) consider(r.lambda);
    if (fall) *fall = rate.window_fall();
    return std::max(done + r.sweeps, 1);
  }
}

}  // namespace dc::solvers::prox
