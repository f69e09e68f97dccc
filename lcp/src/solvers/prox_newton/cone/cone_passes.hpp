#pragma once
// prox-newton's exact-cone outer loop (ProxNewtonDef::exact_cone, body space): hard Coulomb
// friction as the fixed point of convex cone problems (de Saxcé's bipotential: the Coulomb
// law is Anitescu's cone complementarity with the normal velocity shifted by μ|w_t|).
// Pass k, from λ^k with w^k = A λ^k + b:
//     ŝ_n = μ |w_t^k| on each contact's normal row n (t its tangent row), 0 elsewhere,
//     λ^{k+1} = argmin of cone_newton.hpp's subproblem with c = b + ŝ − δ λ^k,
// i.e. the proximal step F ∋ λ ⊥ A λ + b + ŝ + δ(λ − λ^k) ∈ F*. A fixed point λ = λ^k
// satisfies the 2D Coulomb law exactly: on a sliding contact λ is on an edge of F and
// (w_n + μ|w_t|, w_t) ⊥ that edge inside F*, which gives w_n = 0 and w_t opposing λ_t; sticking
// gives w = 0, separating w_n ≥ 0. The shift reads velocities, which the strictly convex
// primal cost determines uniquely, not λ_n (free along A's null space on piles with more
// contact rows than degrees of freedom). Each pass starts Newton from v = W Jᵀ λ^k and keeps
// the factor of the last H (a pass's first direction is CG with it while CG converges).
// δ shrinks by `shrink` after every pass whose subproblem was solved, down to min_shift (the
// proximal point converges faster the smaller δ is; a solved pass's active set starts the next
// one close), and grows by it after one that was not. A pass that does not lower the best hard
// residual counts as a stall.
// Following passes (follow_shift) let ŝ follow the Newton iterate; with trust_radius > 0 within
// a trust region around the pass's starting shift (shift_trust.hpp). Such a pass is accepted
// unless its hard residual rose above trust_accept times the best (then the next pass starts
// from the best iterate, τ shrinks, and δ does not shrink back to this pass's δ until the best
// has fallen trust_forget-fold).
#include <Eigen/Core>
#include <functional>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/prox_newton/cone/cone_newton.hpp"

namespace dc::solvers::prox {

struct ConePassesDef {
  double shift = 1e-4;           ///< first δ relative to max A_ii
  double min_shift = 1e-4;       ///< δ shrinks by `shrink` after every solved pass down to this
  double shrink = 1.0;           ///< (1: δ fixed); an unsolved pass grows it back by `shrink`
  int max_passes = 50;           ///< passes at most
  int inner_iterations = 8;      ///< Newton iterations per pass at most
  double inner_tolerance = 0.1;  ///< pass accuracy relative to max(target, best hard residual)
  int stale_factor_iterations = 25;
  int max_stalls = 3;            ///< passes in a row without a new best hard residual
  int iterations = 0;            ///< Newton iterations of all passes at most
  bool follow_shift = false;     ///< the shift follows the Newton iterate (ConeSubproblem::follow_shift)
  /// With follow_shift: frozen-shift passes until one is solved within this many Newton
  /// iterations (its active set has settled), following ones after (0: from the first pass).
  /// Without the trust region, a following pass that is not solved or raises the hard residual
  /// above the best goes back to frozen passes; with it, see ShiftTrust.
  int follow_after = 2;
  /// With follow_shift: also switch to following passes after a solved frozen pass once the
  /// best hard residual is ≤ this fraction of the start's (0: only by follow_after).
  double follow_below = 0;
  /// The following passes' trust region on the shift (shift_trust.hpp): first τ, its growth and
  /// shrink factor, rejections in a row before going back to frozen passes, the cut of the best
  /// hard residual that grows τ (trust_radius 0: no trust region).
  double trust_radius = 0;
  double trust_grow = 4;
  int trust_retries = 2;
  double trust_fast = 4;
  /// With the trust region, a following pass (solved or not) is accepted when its hard residual
  /// is at most this many times the best before it.
  double trust_accept = 10;
  /// δ does not shrink to a δ whose following pass was rejected until the best hard residual
  /// has fallen to this fraction of the best at that rejection.
  double trust_forget = 0.1;
  int follow_iterations = 8;     ///< Newton iterations per following pass at most
  int anderson = 0;              ///< Anderson acceleration depth of the outer map λ^k ↦ λ^{k+1} (0: none)
  /// Called after every pass with its number (from 1), its subproblem's work and the hard
  /// residual at its iterate [N] (empty: none).
  std::function<void(int, const SubproblemOutcome&, double)> on_pass;
};

struct ConePassesOutcome {
  Eigen::VectorXd best;           ///< the iterate of least hard residual (the start included)
  double best_residual = INFINITY;  ///< its hard natural residual [N]
  int passes = 0, newton = 0, factorizations = 0, analyses = 0, cg = 0, line_search_steps = 0;
  int rejected = 0;  ///< following passes rejected (their iterate dropped for the best)
};

/// ŝ: μ_t |w_t| on the normal row of each friction row t, 0 on every other row [m/s].
void de_saxce_shift(const LcpProblem& p, const Eigen::VectorXd& w, Eigen::VectorXd& shift);

/// The passes from λ (in the cone) until the hard residual is ≤ target, max_stalls passes
/// without a new best, max_passes or the iteration budget. cone is bound to p.
ConePassesOutcome run_cone_passes(const LcpProblem& p, ConeNewton& cone, const Eigen::VectorXd& lambda, double target,
                                  const ConePassesDef& def);

}  // namespace dc::solvers::prox
