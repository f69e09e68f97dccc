#pragma once
// The prox-newton subproblem in body space, for problems with J and M⁻¹ (as MuJoCo and SAP solve
// theirs). With W = Δt M⁻¹ (so A = J W Jᵀ) the box QP of frozen_subproblem.hpp is the dual of
//     min_v  f(v) = ½ vᵀ W⁻¹ v + Σ_i φ_i((J v + c)_i),
//     φ_i(y) = max_{lo_i ≤ λ ≤ hi_i} (−λ y − ½ δ λ²)
// over velocity changes v [m/s] (3 per body): φ_i is y²/(2δ) where λ_i(y) = clamp(−y/δ, lo_i, hi_i)
// is interior and linear beyond (a half-quadratic on normal rows, the Huber friction loss with
// bound s on friction rows), and the optimum gives λ = λ(J v + c), v = W Jᵀ λ. Newton on
//     ∇f = W⁻¹ v − Jᵀ λ(y),   H = W⁻¹ + Jᵀ D J,   D_ii = 1/δ on the quadratic pieces,
// H SPD however many rows are redundant, factorised by CHOLMOD (newton-sparse's FreeBlockFactor
// with every row free; analysis kept while H's pattern holds), then the exact line search of
// exact_line_search.hpp. The stop test is the dual subproblem's own natural residual at λ(y).
#include <Eigen/Core>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/newton_sparse/sparse_factor.hpp"
#include "solvers/prox_newton/frozen_subproblem.hpp"

namespace dc::solvers::prox {

class BodyNewton {
 public:
  BodyNewton() : factor_(true, true, false) {}
  /// Prepares for problem p (needs has_jacobian()): Jᵀ, W, W⁻¹ and the pattern of H.
  void bind(const LcpProblem& p);
  /// max_i A_ii = Δt Σ_j J_ij² (M⁻¹)_j of the bound problem [m/(N·s)].
  [[nodiscard]] double max_diagonal() const { return max_diag_; }
  /// Solves the subproblem from v = W Jᵀ λ; λ becomes λ(J v + c) at the last iterate.
  SubproblemOutcome solve(const FrozenSubproblem& sub, Eigen::VectorXd& lambda);

 private:
  /// λ(y), the quadratic-piece mask D and the dual residual at v; returns that residual.
  double evaluate(const FrozenSubproblem& sub, Eigen::VectorXd& lambda);
  /// H = W⁻¹ + Jᵀ D J with the mask of the last evaluate().
  void assemble_hessian(double delta);

  const LcpProblem* p_ = nullptr;
  SparseRowMatrix Jt_, H_, Winv_diag_;
  Eigen::VectorXd w_, winv_;  // W, W⁻¹ diagonals (3·bodies)
  double max_diag_ = 0.0;
  FreeBlockFactor factor_;
  std::vector<char> all_free_;
  Eigen::VectorXd v_, y_, d_, e_, g_, Jtl_, u_, wt_, dmask_;
};

}  // namespace dc::solvers::prox
