#pragma once
// The prox-newton subproblem in the dual form, for problems without J (files): the strongly
// convex box QP  E(λ) = ½ λᵀ(A + δI)λ + cᵀλ,  lo ≤ λ ≤ hi  (frozen_subproblem.hpp), solved as the
// box LCP  w = (A + δI)λ + c  with fixed bounds by newton-sparse's semismooth Newton (every
// clamped row goes onto its bound in one step, the free block A_FF + δI by CHOLMOD with the
// analysis kept across passes: A + δI has one pattern whatever δ). With fixed bounds no friction
// row is coupled, so each iteration is one factorisation and one solve, no GMRES; newton-sparse's
// line search on the natural map and its PGS fallback globalise it.
#include <Eigen/Core>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "solvers/prox_newton/frozen_subproblem.hpp"

namespace dc::solvers::prox {

class DualNewton {
 public:
  DualNewton() = default;
  /// Binds the problem's A (compressed, symmetric) for the following solves.
  void bind(const SparseRowMatrix& A);
  /// Solves the subproblem from λ (clamped into the frozen box first); λ is the last iterate.
  SubproblemOutcome solve(const FrozenSubproblem& sub, Eigen::VectorXd& lambda);

 private:
  LcpProblem frozen_;              // A + δI, c, the frozen box; no friction coupling
  std::vector<Eigen::Index> diag_; // position of A_ii in frozen_.A's value array
  Eigen::VectorXd a_diag_;         // A_ii
  double delta_ = 0.0;             // δ of frozen_.A
  NewtonSparseSolver newton_;
};

}  // namespace dc::solvers::prox
