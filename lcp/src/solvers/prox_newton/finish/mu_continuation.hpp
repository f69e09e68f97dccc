#pragma once
// prox-newton's continuation in the friction coefficient (ProxNewtonDef::continuation_stages),
// the last finish. On resting piles with more closed contacts than degrees of freedom every
// local route (passes, proximal finish, nncg) can stop on a plateau of near-solutions a small
// factor above the target whose modes differ from a solution's on a few dozen contacts: the
// contacts stick there that slide in the solution, with normal impulses tens of newtons apart
// (docs/solvers.md "Impact steps that stop a few R short"). With μ scaled down the problem is
// closer to the frictionless one (a convex QP), and raising μ in stages from its solution
// starts each stage near a solution of the next: on those impact steps every stage is reached
// by the lead stage or a short proximal finish, and the last one ends on a solution of the
// problem itself. Every solve is a whole prox-newton solve, and the last is of the problem
// itself, so the answer is judged by the hard residual like any other part's.
#include <Eigen/Core>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/prox_newton.hpp"

namespace dc::solvers::prox {

/// p with every friction coefficient scaled by t: the friction rows' μ and the contacts'
/// (p.constraints), everything else as it is. Throws InvalidArgument unless 0 < t ≤ 1.
LcpProblem with_scaled_friction(const LcpProblem& p, double t);

/// The fraction of μ at stage k ≥ 0: t_k = 1 − (1 − first)·2^−k (first, then halving the gap to 1).
double continuation_fraction(double first, int k);

/// True when p has a friction row with μ > 0 (without one there is nothing to continue in).
bool has_friction(const LcpProblem& p);

/// What the continuation did.
struct ContinuationOutcome {
  Eigen::VectorXd lambda;  ///< the answer of the last solve, on p itself
  ProxNewtonStats work;    ///< the solves' work summed (their lead and safeguard sweeps in lead_sweeps)
  int solves = 0;
};

/// def.continuation_stages solves with `def` (its continuation off) of p with μ scaled by
/// continuation_fraction(def.continuation_first, k), each from the previous one's answer (the
/// first from λ⁰), then one of p itself from the last answer; each to `target` [N] within
/// max_sweeps iterations, with no checkpoints. Stops after the first solve that misses its
/// target (the returned λ is then that solve's answer, possibly of a scaled problem).
ContinuationOutcome continuation_solve(const LcpProblem& p, const Eigen::VectorXd& lambda0, const ProxNewtonDef& def,
                                       double target, int max_sweeps);

}  // namespace dc::solvers::prox
