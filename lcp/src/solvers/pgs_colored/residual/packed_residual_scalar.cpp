// The scalar kernel of pgs-colored's packed closing residual (packed_residual.hpp): the reference
// the AVX2 and AVX-512 kernels match bit for bit.
#include <cmath>

#include "solvers/pgs_colored/residual/packed_residual.hpp"
#include "solvers/pgs_manifold_block.hpp"  // DC_PGS_FMA_CLONES

namespace dc::colored {
namespace {

/// The 6 velocity entries of a lane's two bodies (read only).
struct Vel {
  double a0, a1, a2, v0, v1, v2;
};

/// The sweep kernels' scaled residual of lane k.
inline double scaled(const double (*j)[W], const double* b, int k, const Vel& v) {
  const double s0 = std::fma(j[0][k], v.a0, j[1][k] * v.a1);
  const double s1 = std::fma(j[2][k], v.a2, j[3][k] * v.v0);
  const double s2 = std::fma(j[4][k], v.v1, j[5][k] * v.v2);
  return (b[k] + s0) + (s1 + s2);
}

/// |x − ((y < 0) ? 0 : y)| with y = x − w: a normal row's error.
inline double normal_error(double x, double w) {
  const double y = x - w;
  return std::abs(x - ((y < 0.0) ? 0.0 : y));
}

/// |x − min_of(max_of(y, −t), t)| with y = x − w, t = μ·max_of(0, λ_n): a tangent row's error.
inline double tangent_error(double x, double w, double mu, double ln) {
  const double t = mu * max_of(0.0, ln);
  const double y = x - w;
  return std::abs(x - min_of(max_of(y, -t), t));
}

inline void fold(double e, ResidualAcc& acc) {
  if (e != e)
    acc.nan = true;
  else
    acc.r = max_of(acc.r, e);
}

inline Vel velocities(const double* u, std::int32_t la, std::int32_t lb) {
  return Vel{u[la], u[la + 1], u[la + 2], u[lb], u[lb + 1], u[lb + 2]};
}

}  // namespace

[[gnu::optimize("no-tree-slp-vectorize")]] DC_PGS_FMA_CLONES void residual_scalar(
    const Batch* __restrict batches, int b0, int b1, const double* __restrict lam, const double* __restrict diag,
    const double* __restrict u, double omega, ResidualAcc& acc) {
  ResidualAcc a = acc;
  for (int bi = b0; bi < b1; ++bi) {
    const Batch& B = batches[bi];
    const double* x = lam + static_cast<long>(bi) * 2 * W;
    const double* d = diag + static_cast<long>(bi) * 2 * W;
    for (int k = 0; k < B.count; ++k) {
      const Vel v = velocities(u, B.la[k], B.lb[k]);
      fold(normal_error(x[k], (scaled(B.jn, B.bn, k, v) * d[k]) / omega), a);
      fold(tangent_error(x[W + k], (scaled(B.jt, B.bt, k, v) * d[W + k]) / omega, B.mu[k], x[k]), a);
    }
  }
  acc = a;
}

[[gnu::optimize("no-tree-slp-vectorize")]] DC_PGS_FMA_CLONES void residual_pairs_scalar(
    const PairBatch* __restrict pairs, int b0, int b1, const double* __restrict lam, const double* __restrict diag,
    const double* __restrict u, double omega, ResidualAcc& acc) {
  ResidualAcc a = acc;
  for (int bi = b0; bi < b1; ++bi) {
    const PairBatch& P = pairs[bi];
    const double* x = lam + static_cast<long>(bi) * 4 * W;
    const double* d = diag + static_cast<long>(bi) * 4 * W;
    for (int k = 0; k < P.count; ++k) {
      const Vel v = velocities(u, P.la[k], P.lb[k]);
      fold(normal_error(x[k], (scaled(P.jn0, P.bn0, k, v) * d[k])), a);
      fold(tangent_error(x[W + k], (scaled(P.jt0, P.bt0, k, v) * d[W + k]) / omega, P.mu0[k], x[k]), a);
      fold(normal_error(x[2 * W + k], (scaled(P.jn1, P.bn1, k, v) * d[2 * W + k])), a);
      fold(tangent_error(x[3 * W + k], (scaled(P.jt1, P.bt1, k, v) * d[3 * W + k]) / omega, P.mu1[k], x[2 * W + k]),
           a);
    }
  }
  acc = a;
}

}  // namespace dc::colored
