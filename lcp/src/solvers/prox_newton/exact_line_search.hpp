#pragma once
// The exact line search of the body-space subproblem (body_newton.hpp). Along v + t d the cost
//     f(t) = ½ (v + t d)ᵀ W⁻¹ (v + t d) + Σ_i φ_i(y_i + t e_i),   e = J d,
// is convex and piecewise quadratic; its slope
//     f'(t) = a + t q − Σ_i e_i λ_i(y_i + t e_i),   a = dᵀW⁻¹v,  q = dᵀW⁻¹d,
//     λ_i(y) = clamp(−y/δ, lo_i, hi_i)   (the row's multiplier, −φ_i'(y)),
// is continuous, non-decreasing and piecewise linear, with f''(t) = q + Σ_{quadratic rows} e_i²/δ.
// The search finds f'(t) = 0 by Newton's method on f' inside a shrinking bracket (bisection
// when a Newton step leaves it): on a piecewise-linear slope the Newton step is exact as soon
// as it stays on one piece, so it crosses any number of kinks in a few evaluations.
#include <Eigen/Core>
#include <functional>

namespace dc::solvers::prox {

struct LineSearchInput {
  const Eigen::VectorXd* y;   ///< J v + c at t = 0 [m/s]
  const Eigen::VectorXd* e;   ///< J d [m/s]
  const Eigen::VectorXd* lo;  ///< frozen bounds [N]
  const Eigen::VectorXd* hi;
  double delta;               ///< δ [m/(N·s)]
  double a, q;                ///< dᵀW⁻¹v, dᵀW⁻¹d
};

struct LineSearchResult {
  double t = 0;     ///< the minimiser along the line (0 when d is not a descent direction)
  int steps = 0;    ///< evaluations of f'
};

/// f'(t) and f''(t).
void line_slope(const LineSearchInput& in, double t, double& slope, double& curvature);

/// f'(t) and f''(t) of a convex piecewise-quadratic f along a line (slope, curvature).
using SlopeFunction = std::function<void(double t, double& slope, double& curvature)>;

/// The minimiser t ≥ 0 of a convex piecewise-quadratic f given its slope (the search above; the
/// same stops as exact_line_search). t = 0 when f'(0) ≥ 0 or is not finite.
LineSearchResult minimise_along(const SlopeFunction& slope);

/// The minimiser t ≥ 0 of f along d (to |f'(t)| ≤ 1e-12 |f'(0)|, or a bracket of relative
/// width 1e-14; at most 60 evaluations).
LineSearchResult exact_line_search(const LineSearchInput& in);

}  // namespace dc::solvers::prox
