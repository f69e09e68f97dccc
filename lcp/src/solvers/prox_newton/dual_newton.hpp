#pragma once
// The prox-newton subproblem in the dual form, for problems without J (files): projected Newton
// on the strongly convex box QP  E(λ) = ½ λᵀ(A + δI)λ + cᵀλ,  lo ≤ λ ≤ hi  (frozen_subproblem.hpp).
// Iteration at λ with gradient g = (A + δI)λ + c and subproblem residual r:
//   * ε-active rows (ε = r): within ε of a bound with g pushing outwards; they move onto that
//     bound (Δ_C = clamp(λ − g/(A_ii + δ)) − λ);
//   * free rows: Newton on the rest, (A_FF + δI) Δ_F = −g_F − (A Δ_C)_F, the block factorised by
//     newton-sparse's FreeBlockFactor (CHOLMOD, analysis kept while A's pattern holds);
//   * projected Armijo search on E along clamp(λ + αΔ): E(λ_α) ≤ E(λ) + σ gᵀ(λ_α − λ), α halving.
#include <Eigen/Core>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "solvers/newton_sparse/sparse_factor.hpp"
#include "solvers/prox_newton/frozen_subproblem.hpp"

namespace dc::solvers::prox {

class DualNewton {
 public:
  DualNewton() : factor_(true, true, false) {}
  /// Binds the problem's A (compressed, symmetric) for the following solves.
  void bind(const SparseRowMatrix& A);
  /// Solves the subproblem from λ (clamped into the frozen box first); λ is the last iterate.
  SubproblemOutcome solve(const FrozenSubproblem& sub, Eigen::VectorXd& lambda);

 private:
  /// E(λ) and w̃ = (A + δI)λ + c at λ.
  double energy(const FrozenSubproblem& sub, const Eigen::VectorXd& lambda, Eigen::VectorXd& w) const;

  FreeBlockFactor factor_;
  const SparseRowMatrix* A_ = nullptr;
  Eigen::VectorXd diag_;
  std::vector<char> free_;
  Eigen::VectorXd w_, trial_, trial_w_, delta_, rhs_, x_;
};

}  // namespace dc::solvers::prox
