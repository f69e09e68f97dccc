#pragma once
// The 2D friction cone F_μ = {λ : λ_n ≥ 0, |λ_t| ≤ μ λ_n} of one contact and the Euclidean
// projection onto it, the building block of prox-newton's exact-cone subproblem
// (cone_newton.hpp). F_μ is polyhedral: a point z = (z_n, z_t) projects in one of three regions
//   * stick (inside, z ∈ F_μ):                          P(z) = z,         ∂P = I;
//   * separate (the polar cone z_n + μ|z_t| ≤ 0):        P(z) = 0,         ∂P = 0;
//   * slide (elsewhere): onto the edge u = (1, σμ)/√(1+μ²), σ = sign z_t,
//                                                        P(z) = (uᵀz) u,   ∂P = u uᵀ.
// P is piecewise linear and ∂P symmetric positive semidefinite, so ½‖P(z)‖² is convex,
// piecewise quadratic and C¹ with gradient P(z). μ = 0 makes F the ray λ_t = 0, λ_n ≥ 0.
#include <cmath>

namespace dc::solvers::prox {

enum class ConeRegion { Separate = 0, Slide = 1, Stick = 2 };

struct ConePoint {
  double n = 0, t = 0;     ///< P(z)
  double un = 0, ut = 0;   ///< the edge direction u (Slide only)
  ConeRegion region = ConeRegion::Separate;
};

/// P_{F_μ}(z) with its region.
inline ConePoint project_cone(double mu, double zn, double zt) {
  ConePoint p;
  const double at = zt < 0 ? -zt : zt;
  if (zn >= 0 && at <= mu * zn) {
    p.n = zn;
    p.t = zt;
    p.region = ConeRegion::Stick;
    return p;
  }
  if (zn + mu * at <= 0) return p;  // Separate: λ = 0
  const double sigma = zt < 0 ? -1.0 : 1.0;
  const double scale = 1.0 / (1.0 + mu * mu);
  const double s = (zn + sigma * mu * zt) * scale;  // (uᵀz)/√(1+μ²)
  p.n = s;
  p.t = sigma * mu * s;
  const double norm = std::sqrt(scale);
  p.un = norm;
  p.ut = sigma * mu * norm;
  p.region = ConeRegion::Slide;
  return p;
}

/// ∂P at p's region as the symmetric 2×2 (nn, nt, tt).
inline void cone_jacobian(const ConePoint& p, double& nn, double& nt, double& tt) {
  switch (p.region) {
    case ConeRegion::Stick: nn = 1; nt = 0; tt = 1; return;
    case ConeRegion::Slide: nn = p.un * p.un; nt = p.un * p.ut; tt = p.ut * p.ut; return;
    case ConeRegion::Separate: break;
  }
  nn = nt = tt = 0;
}

}  // namespace dc::solvers::prox
