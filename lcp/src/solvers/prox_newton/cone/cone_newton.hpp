#pragma once
// prox-newton's body-space Newton on the exact 2D friction cone (MuJoCo's and Drake SAP's
// primal form), the subproblem of the exact-cone passes (cone_passes.hpp). With W = Δt M⁻¹
// (A = J W Jᵀ) and per-row offsets c [m/s] it minimises over velocity changes v [m/s]
//     f(v) = ½ vᵀ W⁻¹ v + Σ_contacts ℓ_c(y_c) + Σ_other rows ℓ_i(y_i),   y = J v + c,
//     ℓ_c(y) = max_{λ ∈ F_μ} (−λᵀy − ½ δ ‖λ‖²) = ‖P_F(−y)‖² / (2δ),   λ_c(y) = P_F(−y/δ),
// with F_μ the contact's cone (friction_cone.hpp) on its (normal, tangent) rows, and on every
// other row (a normal row without friction, fixed-bound rows) the same with the box [lo, hi]:
// λ_i(y) = clamp(−y/δ, lo_i, hi_i). f is strictly convex, C¹ and piecewise quadratic:
//     ∇f = W⁻¹ v − Jᵀ λ(y),   H = W⁻¹ + Jᵀ G J,   G_c = ∂P_F / δ (2×2: I/δ sticking,
//     u uᵀ/δ sliding, 0 separating), G_i = 1/δ on a box row strictly inside its box.
// Its optimum gives v = W Jᵀ λ and λ = P_F(−(A λ + c)/δ): with c = b + ŝ − δ λ^k that is the
// proximal step on Anitescu's cone complementarity problem with the normal velocities shifted
// by ŝ, F ∋ λ ⊥ A λ + b + ŝ + δ(λ − λ^k) ∈ F*.
// Newton on ∇f = 0: H (SPD) by CHOLMOD (newton-sparse's FreeBlockFactor, analysis kept while
// H's pattern holds, the numeric factor while G and δ do) or by CG preconditioned with the kept
// factor of an earlier G (stale_pcg.hpp, sub.stale_factor_iterations), then the exact line
// search on f along the direction (exact_line_search.hpp's minimise_along). The stop test is
// the subproblem's natural residual max |λ − P(λ − (A λ + c + δ λ))| per contact and row [N].
#include <Eigen/Core>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/newton_sparse/sparse_factor.hpp"
#include "solvers/prox_newton/frozen_subproblem.hpp"

namespace dc::solvers::prox {

struct ConeSubproblem {
  Eigen::VectorXd c;       ///< per-row offset of y = J v + c [m/s]
  double delta = 0;        ///< δ [m/(N·s)]
  double tolerance = 0;    ///< stop when the natural residual is ≤ this [N]
  int max_iterations = 0;  ///< Newton iterations at most
  /// H's direction by CG preconditioned with the kept factor of an earlier H, refactorising
  /// only when CG needs more than this many iterations (0: whenever G or δ changed).
  int stale_factor_iterations = 0;
  /// de Saxcé's shift follows the iterate: y_n gets + μ|(J v + b)_t| of the same v on each
  /// contact (b the problem's), so the subproblem is the proximal step on the exact Coulomb
  /// problem (no potential: F = W⁻¹v − Jᵀλ(y) is no gradient). Its Jacobian
  /// K = W⁻¹ + Jᵀ G (I + S) J, S_nt = μ sign(w_t), is not symmetric: the direction solves
  /// K d = −F by GMRES preconditioned with H's (kept) factor, the step is the longest of 1, ½, …
  /// that lowers FᵀWF by the Armijo fraction, else the exact line search on f with the shift
  /// frozen at the iterate along H's direction.
  bool follow_shift = false;
  /// With follow_shift, a trust region on the shift: when shift_center is not empty (one entry
  /// per row, ŝ⁰ at the pass's start), contact c's normal row gets
  ///     ŝ_n(v) = clamp(μ|w_t(v)|, ŝ⁰_n − shift_radius, ŝ⁰_n + shift_radius)   [m/s],
  /// and S_nt = 0 where the clamp binds (the shift is frozen at the region's edge there).
  /// shift_radius 0 is the frozen-shift pass, +∞ (or an empty centre) the following one.
  Eigen::VectorXd shift_center;
  double shift_radius = 0;
};

class ConeNewton {
 public:
  ConeNewton() : factor_(true, true, false) {}
  /// Prepares for p (needs has_jacobian()): the contacts (friction row t with its normal row
  /// n = normal_row[t]), Jᵀ, W. False when p has no cone form (a friction row whose normal row's
  /// fixed bounds are not [0, +∞)).
  bool bind(const LcpProblem& p);
  /// max_i A_ii = Δt Σ_j J_ij² (M⁻¹)_j of the bound problem [m/(N·s)].
  [[nodiscard]] double max_diagonal() const { return max_diag_; }
  /// Solves the subproblem from v = W Jᵀ λ; λ becomes λ(J v + c) at the last iterate.
  SubproblemOutcome solve(const ConeSubproblem& sub, Eigen::VectorXd& lambda);

  /// f(v), and ∇f(v) into gradient when it is not null (tests check them by differences); with
  /// follow_shift the gradient is F(v) and f the cost with the shift frozen at v.
  double cost(const ConeSubproblem& sub, const Eigen::VectorXd& v, Eigen::VectorXd* gradient);
  /// H(v) x (the generalised Hessian of the region at v); with follow_shift K(v) x, F's Jacobian.
  void hessian_times(const ConeSubproblem& sub, const Eigen::VectorXd& v, const Eigen::VectorXd& x,
                     Eigen::VectorXd& hx);

 private:
  struct Contact {
    int n, t;
    double mu;
  };
  /// v with everything read from it: y, λ(y), G, Jᵀλ, the gradient, the residual, the cost.
  struct Point {
    Eigen::VectorXd v, y, lambda, g, Jtl;
    Eigen::VectorXd gnn, gnt, gtt;  // per contact: G_c δ
    Eigen::VectorXd gs;             // per other row: G_i δ (0 or 1)
    Eigen::VectorXd sig;            // per contact: μ sign(w_t) (follow_shift), else 0
    double residual = 0, cost = 0, merit = 0;  // merit FᵀWF
  };
  /// follow_shift: ŝ_n of contact c at tangential velocity wt [m/s], clamped to the trust region,
  /// and into sig its derivative μ sign(wt) (0 where the clamp binds).
  static double followed_shift(const ConeSubproblem& sub, const Contact& c, double wt, double& sig);
  /// Fills pt from pt.v; with `residual` also the natural residual (a product with A).
  void evaluate(const ConeSubproblem& sub, Point& pt, bool residual);
  /// hx = W⁻¹x + Jᵀ(G (J x)) at pt; with `coupled` K's product W⁻¹x + Jᵀ(G (I + S) J x).
  void multiply(const Point& pt, double delta, const Eigen::VectorXd& x, Eigen::VectorXd& hx, bool coupled = false);
  /// follow_shift: K's direction into d_ by GMRES with the kept factor (refactorised at pt when
  /// GMRES does not converge with it); false when there is none that descends on FᵀWF.
  bool coupled_direction(const ConeSubproblem& sub, const Point& pt, SubproblemOutcome& out, NewtonSparseStats& st);
  /// follow_shift: a backtracking step along d_ that lowers FᵀWF enough (Armijo); false if none.
  bool step_on_merit(const ConeSubproblem& sub, SubproblemOutcome& out);
  /// Factorises H at pt unless the kept factor is of the same G and δ; false on failure.
  bool factorize(const Point& pt, double delta, NewtonSparseStats& st);
  /// d_ = −H⁻¹ g_ at pt (CG with the kept factor when allowed and it converges); false on failure.
  bool newton_direction(const ConeSubproblem& sub, const Point& pt, SubproblemOutcome& out, NewtonSparseStats& st);
  /// f'(t), f''(t) along cur_ + t d_ (e_ = J d_, a = d_ᵀW⁻¹v, q = d_ᵀW⁻¹d_).
  void slope(double delta, double a, double q, double t, double& s, double& curvature) const;
  /// The G entries of pt in one vector (the kept factor's key).
  static void g_key(const Point& pt, Eigen::VectorXd& key);

  const LcpProblem* p_ = nullptr;
  std::vector<Contact> contacts_;
  std::vector<int> others_;  // rows outside any cone, with fixed bounds
  SparseRowMatrix Jt_, Winv_diag_, H_;
  Eigen::VectorXd w_, winv_;
  double max_diag_ = 0.0;
  FreeBlockFactor factor_;
  std::vector<char> all_free_;
  Eigen::VectorXd factored_key_, key_;
  double factored_delta_ = 0.0;
  Point cur_, trial_;
  Eigen::VectorXd d_, e_, g_, u_, wt_, jx_, kx_;
};

}  // namespace dc::solvers::prox
