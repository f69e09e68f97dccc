#pragma once
// The prox-newton subproblem in body space, for problems with J and M⁻¹ (as MuJoCo and SAP solve
// theirs). With W = Δt M⁻¹ (so A = J W Jᵀ) the box QP of frozen_subproblem.hpp is the dual of
//     min_v  f(v) = ½ vᵀ W⁻¹ v + Σ_i φ_i((J v + c)_i),
//     φ_i(y) = max_{lo_i ≤ λ ≤ hi_i} (−λ y − ½ δ λ²)
// over velocity changes v [m/s] (3 per body): φ_i is y²/(2δ) where λ_i(y) = clamp(−y/δ, lo_i, hi_i)
// is interior and linear beyond (a half-quadratic on normal rows, the Huber friction loss with
// bound s on friction rows), and the optimum gives λ = λ(J v + c), v = W Jᵀ λ. Newton on
//     F(v) = ∇f = W⁻¹ v − Jᵀ λ(y),   H = W⁻¹ + Jᵀ D J,   D_ii = 1/δ on the quadratic pieces,
// H SPD however many rows are redundant, factorised by CHOLMOD (newton-sparse's FreeBlockFactor
// with every row free; analysis kept while H's pattern holds, the factor kept while D and δ
// do), then the exact line search of exact_line_search.hpp. With sub.stale_factor_iterations the
// direction comes from CG preconditioned with the kept factor of an earlier D (stale_pcg.hpp)
// while CG converges within that many iterations, and H is refactorised only when it does not.
//
// Coupled (sub.coupled, the hard proximal subproblem): a friction row's bound follows the
// iterate, s_t = μ max(0, λ_n(y)). F(v) = 0 is then no gradient (Coulomb friction has no
// potential): its Jacobian K = H + Jᵀ C J adds C_tn = σ μ/δ for a friction row t on the bound
// σ s_t whose normal row n is interior. The direction solves K d = −F by GMRES preconditioned
// with H's factor (K H⁻¹ − I has rank ≤ the sliding rows): semismooth Newton, as newton-sparse's
// coupled step. The step is the longest of t = 1, ½, ¼, … that lowers the merit FᵀWF by the
// Armijo fraction; when none does, the exact line search on the cost with the current
// iterate's bounds frozen (along a descent direction of that cost: K's when it is one, else
// H's), and the bounds follow at the next iterate.
// The stop test is the dual subproblem's natural residual at λ(y) against λ's own bounds.
#include <Eigen/Core>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/newton_sparse/sparse_factor.hpp"
#include "solvers/prox_newton/body/normal_matrix.hpp"
#include "solvers/prox_newton/frozen_subproblem.hpp"

namespace dc::solvers::prox {

class BodyNewton {
 public:
  BodyNewton() : factor_(true, true, false) {}
  /// Prepares for problem p (needs has_jacobian()): Jᵀ, W, W⁻¹ and the pattern of H.
  void bind(const LcpProblem& p);
  /// Drops the kept factor: the next direction comes from a fresh factorisation.
  void forget_factor() { factored_mask_.resize(0); }
  /// max_i A_ii = Δt Σ_j J_ij² (M⁻¹)_j of the bound problem [m/(N·s)].
  [[nodiscard]] double max_diagonal() const { return max_diag_; }
  /// Solves the subproblem from v = W Jᵀ λ; λ becomes λ(J v + c) at the last iterate.
  SubproblemOutcome solve(const FrozenSubproblem& sub, Eigen::VectorXd& lambda);

 private:
  /// The point v_ with everything read from it: y, λ(y), its bounds, D, C, Jᵀλ, the residual.
  struct Point {
    Eigen::VectorXd v, y, lambda, lo, hi, dmask, coupling, Jtl, g;
    double residual = 0, merit = 0;  // dual residual [N]; FᵀWF
  };
  /// Fills pt from pt.v: λ(y), the bounds and masks, and the dual residual; returns it.
  double evaluate(const FrozenSubproblem& sub, Point& pt);
  /// Factorises H for pt's D unless the kept factor is of the same D and δ; false on failure.
  bool factorize(const Point& pt, double delta, NewtonSparseStats& st);
  /// H's Newton direction d_ = −H⁻¹g_ at pt: by CG with the kept factor when sub allows it and
  /// CG converges, else from a fresh factorisation of H; false on failure.
  bool newton_direction(const FrozenSubproblem& sub, const Point& pt, SubproblemOutcome& out, NewtonSparseStats& st);
  /// hx = W⁻¹x + Jᵀ(D∘(Jx)) at pt: H's product; with `coupled`, also + Jᵀ(C(Jx)) (the coupled
  /// system K, C_tn = coupling_t on the normal row n of friction row t).
  void multiply(const Point& pt, const Eigen::VectorXd& x, Eigen::VectorXd& hx, bool coupled);
  /// The Newton direction d_ at pt (H's already in d_): coupled (GMRES) when sliding rows couple, else H⁻¹; the
  /// result is a descent direction of the cost with pt's bounds frozen. False when none.
  bool direction(const FrozenSubproblem& sub, const Point& pt, SubproblemOutcome& out, bool& coupled_step);

  /// Coupled: a backtracking step along d_ that lowers FᵀWF enough (Armijo); false if none.
  bool step_on_merit(const FrozenSubproblem& sub, SubproblemOutcome& out);

  const LcpProblem* p_ = nullptr;
  SparseRowMatrix Jt_, Winv_diag_;
  NormalMatrix normal_;  // H = W⁻¹ + Jᵀ D J in J's fixed pattern
  Eigen::VectorXd w_, winv_;  // W, W⁻¹ diagonals (3·bodies)
  double max_diag_ = 0.0;
  FreeBlockFactor factor_;
  std::vector<char> all_free_;
  std::vector<int> friction_, other_;  // row indices by kind, in order
  Eigen::VectorXd factored_mask_;      // D of the kept factor (empty: none)
  double factored_delta_ = 0.0;
  Point cur_, trial_;
  Eigen::VectorXd d_, e_, g_, u_, wt_, jx_, kx_;
};

}  // namespace dc::solvers::prox
