// The scalar colour kernel of "pgs-colored" (pgs_colored_batch.hpp): the reference the AVX2 and
// AVX-512 kernels match bit for bit, and the kernel of CPUs without them. Per contact it performs
// the operations of "pgs"'s contact block: r = (b + fma(j0,a0,j1·a1)) + (fma(j2,a2,j3·b0) +
// fma(j4,b1,j5·b2)); the clamps max(y,0), max(0,λ_n), clamp(y,−t,t) are written as the
// compare-and-select of the vector kernels (the same value for ±0 and NaN as std::max/min).
#include <cmath>

#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_manifold_block.hpp"  // DC_PGS_FMA_CLONES

namespace dc::colored {
namespace {

/// True when one of the six values is ±∞ or NaN: x·0 is ±0 for finite x and NaN otherwise,
/// and a sum of ±0 stays ±0 (the vector kernels compute exactly this, lane by lane).
inline bool any_nonfinite(double a0, double a1, double a2, double v0, double v1, double v2) {
  const double z = ((a0 * 0.0 + a1 * 0.0) + (a2 * 0.0 + v0 * 0.0)) + (v1 * 0.0 + v2 * 0.0);
  return z != z;
}

/// The 6 velocity entries of a lane's two bodies, updated in registers by every row of the lane.
struct Vel {
  double a0, a1, a2, v0, v1, v2;
};

/// Scaled residual (b + fma(j0,a0,j1·a1)) + (fma(j2,a2,j3·v0) + fma(j4,v1,j5·v2)) of lane k.
inline double residual(const double (*j)[W], const double* b, int k, const Vel& v) {
  const double s0 = std::fma(j[0][k], v.a0, j[1][k] * v.a1);
  const double s1 = std::fma(j[2][k], v.a2, j[3][k] * v.v0);
  const double s2 = std::fma(j[4][k], v.v1, j[5][k] * v.v2);
  return (b[k] + s0) + (s1 + s2);
}

/// Δu += (M⁻¹ J_iᵀ Δt)·d on lane k's 6 slots.
inline void update(const double (*mj)[W], int k, double d, Vel& v) {
  v.a0 = std::fma(mj[0][k], d, v.a0);
  v.a1 = std::fma(mj[1][k], d, v.a1);
  v.a2 = std::fma(mj[2][k], d, v.a2);
  v.v0 = std::fma(mj[3][k], d, v.v0);
  v.v1 = std::fma(mj[4][k], d, v.v1);
  v.v2 = std::fma(mj[5][k], d, v.v2);
}

/// A pair lane's tangent row: bound μ·max(0, λ_n) from the previous sweep's λ_n (the contact
/// kernel's clamp and flags).
inline void pair_tangent(const double (*jt)[W], const double (*mjt)[W], const double* bt, const double* mu, int k,
                         double ln, double old, double& x_out, Vel& v, double& theta, bool& bad) {
  const double res = residual(jt, bt, k, v);
  const double t = mu[k] * max_of(0.0, ln);
  const double y = old - res;
  const double c = min_of(max_of(y, -t), t);
  const bool active = 0.0 < t;
  const double x = active ? c : 0.0;
  bad |= !std::isfinite(active ? x : y);
  const double d = x - old;
  x_out = x;
  update(mjt, k, d, v);
  theta = max_of(theta, std::abs(d));
}

/// A pair lane's 2 × 2 normal block (pgs_colored_batch.hpp: the four cases, then Gauss–Seidel).
inline void pair_normals(const PairBatch& P, int k, double l0, double l1, double& x0_out, double& x1_out, Vel& v,
                         double& theta, bool& bad) {
  const double res0 = residual(P.jn0, P.bn0, k, v);
  const double res1 = residual(P.jn1, P.bn1, k, v);
  const double c01 = P.c01[k], c10 = P.c10[k], inv_det = P.inv_det[k];
  const double beta0 = (res0 - l0) - c01 * l1;
  const double beta1 = (res1 - l1) - c10 * l0;
  const double both0 = (c01 * beta1 - beta0) * inv_det;
  const double both1 = (c10 * beta0 - beta1) * inv_det;
  const double nb0 = -beta0, nb1 = -beta1;
  const double y0 = l0 - res0;
  const double f0 = (y0 < 0.0) ? 0.0 : y0;
  const double y1 = l1 - (res1 + c10 * (f0 - l0));
  const double f1 = (y1 < 0.0) ? 0.0 : y1;
  const bool blk = 0.0 < P.block[k];
  const bool case1 = blk && both0 >= 0.0 && both1 >= 0.0;
  const bool case2 = blk && nb0 >= 0.0 && c10 * nb0 + beta1 >= 0.0;
  const bool case3 = blk && nb1 >= 0.0 && c01 * nb1 + beta0 >= 0.0;
  const bool case4 = blk && beta0 >= 0.0 && beta1 >= 0.0;
  const double x0 = case1 ? both0 : case2 ? nb0 : (case3 || case4) ? 0.0 : f0;
  const double x1 = case1 ? both1 : case2 ? 0.0 : case3 ? nb1 : case4 ? 0.0 : f1;
  bad |= !std::isfinite(x0) || !std::isfinite(x1);
  const double d0 = x0 - l0, d1 = x1 - l1;
  x0_out = x0;
  x1_out = x1;
  update(P.mjn0, k, d0, v);
  update(P.mjn1, k, d1, v);
  theta = max_of(theta, std::abs(d0));
  theta = max_of(theta, std::abs(d1));
}

}  // namespace

[[gnu::optimize("no-tree-slp-vectorize")]] DC_PGS_FMA_CLONES void sweep_pairs_scalar(
    const PairBatch* __restrict pairs, int b0, int b1, const double* __restrict in, double* __restrict out,
    double* __restrict u, Acc& acc) {
  double theta = acc.theta;
  bool bad = acc.bad;
  for (int bi = b0; bi < b1; ++bi) {
    const PairBatch& P = pairs[bi];
    const double* lin = in + static_cast<long>(bi) * 4 * W;
    double* lout = out + static_cast<long>(bi) * 4 * W;
    for (int k = 0; k < P.count; ++k) {
      const double* ua = u + P.la[k];
      const double* ub = u + P.lb[k];
      Vel v{ua[0], ua[1], ua[2], ub[0], ub[1], ub[2]};
      const double l0 = lin[k], l1 = lin[2 * W + k];
      pair_tangent(P.jt0, P.mjt0, P.bt0, P.mu0, k, l0, lin[W + k], lout[W + k], v, theta, bad);
      pair_tangent(P.jt1, P.mjt1, P.bt1, P.mu1, k, l1, lin[3 * W + k], lout[3 * W + k], v, theta, bad);
      pair_normals(P, k, l0, l1, lout[k], lout[2 * W + k], v, theta, bad);
      bad |= any_nonfinite(v.a0, v.a1, v.a2, v.v0, v.v1, v.v2);
      if (P.ka[k]) {
        double* sa = u + P.la[k];
        sa[0] = v.a0;
        sa[1] = v.a1;
        sa[2] = v.a2;
      }
      if (P.kb[k]) {
        double* sb = u + P.lb[k];
        sb[0] = v.v0;
        sb[1] = v.v1;
        sb[2] = v.v2;
      }
    }
  }
  acc.theta = theta;
  acc.bad = bad;
}

[[gnu::optimize("no-tree-slp-vectorize")]] DC_PGS_FMA_CLONES void sweep_scalar(const Batch* __restrict batches, int b0,
                                                                                 int b1, const double* __restrict in,
                                                                                 double* __restrict out,
                                                                                 double* __restrict u, Acc& acc) {
  double theta = acc.theta;
  bool bad = acc.bad;
  for (int bi = b0; bi < b1; ++bi) {
    const Batch& B = batches[bi];
    const double* ln_in = in + static_cast<long>(bi) * 2 * W;
    double* ln = out + static_cast<long>(bi) * 2 * W;
    for (int k = 0; k < B.count; ++k) {
      const double* ua = u + B.la[k];
      const double* ub = u + B.lb[k];
      double a0 = ua[0], a1 = ua[1], a2 = ua[2], v0 = ub[0], v1 = ub[1], v2 = ub[2];
      double xn;
      {
        const double s0 = std::fma(B.jn[0][k], a0, B.jn[1][k] * a1);
        const double s1 = std::fma(B.jn[2][k], a2, B.jn[3][k] * v0);
        const double s2 = std::fma(B.jn[4][k], v1, B.jn[5][k] * v2);
        const double res = (B.bn[k] + s0) + (s1 + s2);
        const double old = ln_in[k];
        const double y = old - res;
        xn = (y < 0.0) ? 0.0 : y;
        bad |= !std::isfinite(xn);
        const double d = xn - old;
        ln[k] = xn;
        a0 = std::fma(B.mjn[0][k], d, a0);
        a1 = std::fma(B.mjn[1][k], d, a1);
        a2 = std::fma(B.mjn[2][k], d, a2);
        v0 = std::fma(B.mjn[3][k], d, v0);
        v1 = std::fma(B.mjn[4][k], d, v1);
        v2 = std::fma(B.mjn[5][k], d, v2);
        theta = max_of(theta, std::abs(d));
      }
      {
        const double s0 = std::fma(B.jt[0][k], a0, B.jt[1][k] * a1);
        const double s1 = std::fma(B.jt[2][k], a2, B.jt[3][k] * v0);
        const double s2 = std::fma(B.jt[4][k], v1, B.jt[5][k] * v2);
        const double res = (B.bt[k] + s0) + (s1 + s2);
        const double old = ln_in[W + k];
        const double t = B.mu[k] * max_of(0.0, xn);
        const double y = old - res;
        const double c = min_of(max_of(y, -t), t);
        const bool active = 0.0 < t;
        const double x = active ? c : 0.0;
        bad |= !std::isfinite(active ? x : y);
        const double d = x - old;
        ln[W + k] = x;
        a0 = std::fma(B.mjt[0][k], d, a0);
        a1 = std::fma(B.mjt[1][k], d, a1);
        a2 = std::fma(B.mjt[2][k], d, a2);
        v0 = std::fma(B.mjt[3][k], d, v0);
        v1 = std::fma(B.mjt[4][k], d, v1);
        v2 = std::fma(B.mjt[5][k], d, v2);
        theta = max_of(theta, std::abs(d));
      }
      bad |= any_nonfinite(a0, a1, a2, v0, v1, v2);
      if (B.ka[k]) {
        double* sa = u + B.la[k];
        sa[0] = a0;
        sa[1] = a1;
        sa[2] = a2;
      }
      if (B.kb[k]) {
        double* sb = u + B.lb[k];
        sb[0] = v0;
        sb[1] = v1;
        sb[2] = v2;
      }
    }
  }
  acc.theta = theta;
  acc.bad = bad;
}

}  // namespace dc::colored
