#pragma once
// Newton-type solver for a box LCP with FIXED bounds, the inner solver of "newton" (and of
// the polish step of "lemke"):
//
//     w = A λ + c,   lo ≤ λ ≤ hi,   H(λ)_i = λ_i − mid(lo_i, λ_i − w_i, hi_i) = 0.
//
// Newton direction (minimum map): H is piecewise linear; its generalised Jacobian has
// identity rows for the clamped rows (λ_i − w_i ≤ lo_i or ≥ hi_i: Δ_i = bound − λ_i) and rows
// of A for the free set F, so a step solves only (A_FF + ρI) Δ_F = −(w_F + A_FC Δ_C).
// ρ = 1e-10·max_i A_ii regularises the free blocks of rank-deficient contact matrices
// J M⁻¹ Jᵀ (more rows than body dofs), whose A_FF is singular.
//
// Globalisation:
//  * symmetric A (every contact problem): the box LCP is the convex box QP
//    min q(λ) = ½λᵀAλ + cᵀλ, lo ≤ λ ≤ hi. Each iteration is one projected Gauss–Seidel sweep
//    (always decreases q, fixes the active set) followed by the Newton step along the
//    projection arc P(λ + αΔ) with Armijo backtracking on q. Both parts are monotone in q,
//    so the iteration cannot cycle; once the active set is right the Newton step is exact.
//  * non-symmetric A (general LCPs from files): Armijo backtracking on ½‖H‖²; when it fails
//    a PGS sweep is taken instead (no global guarantee; the caller falls back to PGS).
#include <functional>
#include <string>

#include "dc/engine/lcp_problem.hpp"

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
