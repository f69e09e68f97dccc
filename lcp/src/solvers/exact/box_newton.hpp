#pragma once
// Newton-type solver for a box LCP with FIXED bounds, the inner solver of "newton" (and of
// "lemke"'s polish):  w = A λ + c,  lo ≤ λ ≤ hi,  H(λ)_i = λ_i − mid(lo_i, λ_i − w_i, hi_i) = 0.
// Minimum-map Newton: clamped rows get Δ_i = bound − λ_i, the free set F solves
// (A_FF + ρI) Δ_F = −(w_F + A_FC Δ_C), ρ = 1e-10·max_i A_ii (A_FF of J M⁻¹ Jᵀ is singular
// when there are more rows than body dofs). Globalisation:
//  * symmetric A (every contact problem): the convex box QP min ½λᵀAλ + cᵀλ; each iteration is
//    a PGS sweep (decreases q, fixes the active set), then the Newton step along the projection
//    arc P(λ + αΔ) with Armijo backtracking on q. Both are monotone in q, so it cannot cycle;
//    with the right active set the Newton step is exact.
//  * non-symmetric A (general LCPs from files): Armijo backtracking on ½‖H‖²; when it fails
//    a PGS sweep is taken instead (no global guarantee; the caller falls back to PGS).
#include <functional>
#include <string>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::solvers {

/// How box_newton ended (callers decide on this, never on the text of `why`).
enum class BoxNewtonStop {
  Converged,       ///< ‖H‖∞ ≤ target
  NonFinite,       ///< the residual became non-finite
  IterationLimit,  ///< max_iter iterations without reaching the target
  NoProgress,      ///< the Newton direction or its line search failed repeatedly
};

struct BoxNewtonOutcome {
  bool converged = false;  ///< stop == Converged
  BoxNewtonStop stop = BoxNewtonStop::IterationLimit;
  int iterations = 0;
  double residual = 0.0;  ///< ‖H‖∞ at the returned λ
  std::string why;        ///< the reason in words when not converged (messages only)
};

struct BoxNewtonSystem {
  const SparseRowMatrix& A;
  bool symmetric;  ///< QP globalisation and sparse LDLᵀ (else ‖H‖² merit and sparse LU)
  double rho;      ///< regularisation of the free block (Jacobian only)
  const Eigen::VectorXd& c;
  const Eigen::VectorXd& lo;
  const Eigen::VectorXd& hi;
};

/// Iterates from λ (projected onto the box first) until ‖H‖∞ ≤ target or max_iter
/// iterations. `on_step(λ, step)` is called after every iteration with max_i |Δλ_i|.
BoxNewtonOutcome box_newton(const BoxNewtonSystem& s, Eigen::VectorXd& lambda, double target, int max_iter,
                            const std::function<void(const Eigen::VectorXd&, double)>& on_step);

/// True when A equals Aᵀ to 1e-12 relative (Frobenius norm).
bool is_symmetric(const SparseRowMatrix& A);

}  // namespace dc::solvers
