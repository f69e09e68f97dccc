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

}  // namespace

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
