#include "solvers/prox_newton/finish/mu_continuation.hpp"

#include <cmath>
#include <cstddef>

#include "dc/core/error.hpp"

namespace dc::solvers::prox {

LcpProblem with_scaled_friction(const LcpProblem& p, double t) {
  if (!(t > 0 && t <= 1)) throw InvalidArgument("with_scaled_friction: the fraction of mu must be in (0, 1]");
  LcpProblem q = p;
  for (int i = 0; i < q.rows(); ++i)
    if (q.is_friction_row(i)) q.mu[i] = p.mu[i] * t;
  const auto contacts = static_cast<std::size_t>(p.constraints.size());
  if (contacts > 0) {
    const auto out = q.constraints.overwrite(contacts, p.constraints.rows());
    for (std::size_t c = 0; c < contacts; ++c) {
      out[c] = p.constraints[static_cast<int>(c)];
      out[c].mu *= t;  // μ > 0 stays > 0: the contact keeps its tangent row
    }
  }
  return q;
}

double continuation_fraction(double first, int k) { return 1.0 - (1.0 - first) * std::ldexp(1.0, -k); }

bool has_friction(const LcpProblem& p) {
  for (int i = 0; i < p.rows(); ++i)
    if (p.is_friction_row(i) && p.mu[i] > 0) return true;
  return false;
}

namespace {

void add_work(ProxNewtonStats& sum, const ProxNewtonStats& s) {
  sum.lead_sweeps += s.lead_sweeps + s.safeguard_sweeps;
  sum.outer += s.outer;
  sum.newton += s.newton;
  sum.finish_newton += s.finish_newton;
  sum.factorizations += s.factorizations;
  sum.analyses += s.analyses;
  sum.pivots += s.pivots;
}

}  // namespace

ContinuationOutcome continuation_solve(const LcpProblem& p, const Eigen::VectorXd& lambda0, const ProxNewtonDef& def,
                                       double target, int max_sweeps) {
  ProxNewtonDef inner = def;
  inner.continuation_stages = 0;
  ProxNewtonSolver solver(inner);  // one object: CHOLMOD's analysis serves every stage (same J)
  SolverOptions o;
  o.tolerance = target;
  o.max_sweeps = max_sweeps;
  o.record_theta = false;
  ContinuationOutcome out;
  out.lambda = lambda0;
  for (int k = 0; k <= def.continuation_stages; ++k) {
    const bool last = k == def.continuation_stages;
    const LcpProblem scaled = last ? LcpProblem{} : with_scaled_friction(p, continuation_fraction(def.continuation_first, k));
    const LcpProblem& q = last ? p : scaled;
    const SolveResult r = solver.solve(q, out.lambda, o);
    add_work(out.work, solver.last_stats());
    ++out.solves;
    const bool usable = r.lambda.size() == p.rows() && r.lambda.allFinite();
    if (usable) out.lambda = r.lambda;
    // A stage that missed its target has lost the branch: the later stages would start from
    // no solution, at the cost of a whole solve each (on piles where every solve misses, up to
    // stages + 1 times a failed solve's work).
    if (!usable || !(natural_residual(q, r.lambda) <= target)) break;
  }
  return out;
}

}  // namespace dc::solvers::prox
