// The two-point manifold block kernel of the matrix-free PGS: the formulas, the order and the
// conditioning test are in pgs_manifold_block.hpp. Like the kernels of pgs_matrix_free.cpp,
// the 6 velocity entries of the manifold's two bodies are loaded once, updated in registers
// by every row of the manifold, and stored once.
#include "solvers/pgs_manifold_block.hpp"

#include "solvers/solver_common.hpp"

#include <algorithm>
#include <cmath>

namespace dc::solvers {
namespace {

/// The 6 velocity entries (body a: v_x, v_y, ω; body b: v_x, v_y, ω) of a manifold's bodies.
struct PairVel {
  double a0, a1, a2, b0, b1, b2;
};

/// Scaled residual b + J·Δu with the tree sum of the other kernels (a left-to-right sum of
/// 7 terms would put 6 serial adds on the dependency chain).
inline double residual(const std::array<double, 6>& j, double b, const PairVel& v) {
  const double s0 = std::fma(j[0], v.a0, j[1] * v.a1);
  const double s1 = std::fma(j[2], v.a2, j[3] * v.b0);
  const double s2 = std::fma(j[4], v.b1, j[5] * v.b2);
  return (b + s0) + (s1 + s2);
}

/// Δu += (M⁻¹ Jᵀ Δt) d on the manifold's bodies.
inline void apply(const std::array<double, 6>& mj, double d, PairVel& v) {
  v.a0 = std::fma(mj[0], d, v.a0);
  v.a1 = std::fma(mj[1], d, v.a1);
  v.a2 = std::fma(mj[2], d, v.a2);
  v.b0 = std::fma(mj[3], d, v.b0);
  v.b1 = std::fma(mj[4], d, v.b1);
  v.b2 = std::fma(mj[5], d, v.b2);
}

/// Friction row: λ_t ← clamp(λ_t − r_t, −μ max(0, λ_n), μ max(0, λ_n)), as in sweep_contacts
/// (the t = 0 case as a predictable branch that hands back 0).
inline void tangent_row(const std::array<double, 6>& jt, const std::array<double, 6>& mjt, double bt, double mu,
                        double lambda_n, double& lam_t, PairVel& v, double& theta, bool& bad) {
  const double res = residual(jt, bt, v);
  const double old = lam_t;
  const double t = mu * std::max(0.0, lambda_n);
  const double y = old - res;
  const double x = friction_clamp(y, t, bad);
  const double d = x - old;
  lam_t = x;
  apply(mjt, d, v);
  theta = std::max(theta, std::abs(d));
}

/// max(y, 0) with NaN propagated.
inline double nonneg(double y) { return y < 0.0 ? 0.0 : y; }

/// The 2 × 2 normal block (pgs_manifold_block.hpp: total enumeration, row-by-row fallback).
inline void normal_block(const ManifoldBlock& c, double& lam0, double& lam1, PairVel& v, double& theta, bool& bad) {
  const double res0 = residual(c.jn0, c.bn0, v);
  const double res1 = residual(c.jn1, c.bn1, v);
  const double l0 = lam0, l1 = lam1;
  const double beta0 = (res0 - l0) - c.c01 * l1;
  const double beta1 = (res1 - l1) - c.c10 * l0;
  double x0, x1;
  const double both0 = (c.c01 * beta1 - beta0) * c.inv_det;
  const double both1 = (c.c10 * beta0 - beta1) * c.inv_det;
  if (both0 >= 0.0 && both1 >= 0.0) {  // 1. both points active (a resting face)
    x0 = both0;
    x1 = both1;
  } else if (-beta0 >= 0.0 && c.c10 * -beta0 + beta1 >= 0.0) {  // 2. point 0 only
    x0 = -beta0;
    x1 = 0.0;
  } else if (-beta1 >= 0.0 && c.c01 * -beta1 + beta0 >= 0.0) {  // 3. point 1 only
    x0 = 0.0;
    x1 = -beta1;
  } else if (beta0 >= 0.0 && beta1 >= 0.0) {  // 4. neither (separating)
    x0 = 0.0;
    x1 = 0.0;
  } else {  // round-off at a case boundary, or NaN: the row-by-row update of the two rows
    x0 = nonneg(l0 - res0);
    x1 = nonneg(l1 - (res1 + c.c10 * (x0 - l0)));
  }
  bad |= !std::isfinite(x0) || !std::isfinite(x1);
  const double d0 = x0 - l0, d1 = x1 - l1;
  lam0 = x0;
  lam1 = x1;
  apply(c.mjn0, d0, v);
  apply(c.mjn1, d1, v);
  theta = std::max(theta, std::max(std::abs(d0), std::abs(d1)));
}

template <bool Friction>
inline void sweep(const ManifoldBlock* __restrict c, int count, double* __restrict lam, double* __restrict u,
                  SweepAcc& acc) {
  double theta = acc.theta;
  bool bad = acc.bad;
  constexpr int kRows = Friction ? 4 : 2;
  for (int k = 0; k < count; ++k, ++c, lam += kRows) {
    const double* ua = u + c->la;
    const double* ub = u + c->lb;
    PairVel v{ua[0], ua[1], ua[2], ub[0], ub[1], ub[2]};
    if constexpr (Friction) {
      // lam: n0, t0, n1, t1. Tangent rows first, bounds from the current λ_n (Box2D's order).
      tangent_row(c->jt0, c->mjt0, c->bt0, c->mu0, lam[0], lam[1], v, theta, bad);
      tangent_row(c->jt1, c->mjt1, c->bt1, c->mu1, lam[2], lam[3], v, theta, bad);
      normal_block(*c, lam[0], lam[2], v, theta, bad);
    } else {
      normal_block(*c, lam[0], lam[1], v, theta, bad);
    }
    double* sa = u + c->sa;
    double* sb = u + c->sb;
    sa[0] = v.a0;
    sa[1] = v.a1;
    sa[2] = v.a2;
    sb[0] = v.b0;
    sb[1] = v.b1;
    sb[2] = v.b2;
  }
  acc.theta = theta;
  acc.bad = bad;
}

}  // namespace

DC_PGS_FMA_CLONES void sweep_manifolds_friction(const ManifoldBlock* c, int count, double* lam, double* u,
                                                SweepAcc& acc) {
  sweep<true>(c, count, lam, u, acc);
}

DC_PGS_FMA_CLONES void sweep_manifolds_frictionless(const ManifoldBlock* c, int count, double* lam, double* u,
                                                    SweepAcc& acc) {
  sweep<false>(c, count, lam, u, acc);
}

}  // namespace dc::solvers
