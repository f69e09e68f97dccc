// The AVX2 kernel of pgs-colored's packed closing residual (packed_residual.hpp): a batch as two
// groups of 4 lanes, compiled for AVX2 + FMA by function attribute and chosen at run time. Per
// lane the operations of residual_scalar in its order (explicit FMAs, the same tree sums, the
// clamps as the sweep kernels' compare-and-select), so the errors are the scalar kernel's bits.
#include "solvers/pgs_colored/residual/packed_residual.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#define DC_AVX2 __attribute__((target("avx2,fma")))

namespace dc::colored {
namespace {

/// x = (v_x of lanes 0–3), y = (v_y …), w = (ω …) of the bodies at Δu offsets off[0..3]
/// (the sweep kernel's transpose, pgs_colored_avx2.cpp).
DC_AVX2 inline void load4(const double* u, const std::int32_t* off, __m256d& x, __m256d& y, __m256d& w) {
  const __m256d r0 = _mm256_loadu_pd(u + off[0]), r1 = _mm256_loadu_pd(u + off[1]);
  const __m256d r2 = _mm256_loadu_pd(u + off[2]), r3 = _mm256_loadu_pd(u + off[3]);
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1);
  const __m256d t1 = _mm256_unpackhi_pd(r0, r1);
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3);
  const __m256d t3 = _mm256_unpackhi_pd(r2, r3);
  x = _mm256_permute2f128_pd(t0, t2, 0x20);
  w = _mm256_permute2f128_pd(t0, t2, 0x31);
  y = _mm256_permute2f128_pd(t1, t3, 0x20);
}

DC_AVX2 inline __m256d L(const double* p) { return _mm256_load_pd(p); }
DC_AVX2 inline __m256d LU(const double* p) { return _mm256_loadu_pd(p); }

struct Vel4 {
  __m256d a0, a1, a2, v0, v1, v2;
};

DC_AVX2 inline __m256d scaled(const double (*j)[W], const double* b, int h, const Vel4& v) {
  const __m256d s0 = _mm256_fmadd_pd(L(j[0] + h), v.a0, _mm256_mul_pd(L(j[1] + h), v.a1));
  const __m256d s1 = _mm256_fmadd_pd(L(j[2] + h), v.a2, _mm256_mul_pd(L(j[3] + h), v.v0));
  const __m256d s2 = _mm256_fmadd_pd(L(j[4] + h), v.v1, _mm256_mul_pd(L(j[5] + h), v.v2));
  return _mm256_add_pd(_mm256_add_pd(L(b + h), s0), _mm256_add_pd(s1, s2));
}

DC_AVX2 inline __m256d absv(__m256d x) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), x); }

/// |x − ((y < 0) ? +0 : y)|, y = x − w.
DC_AVX2 inline __m256d normal_error(__m256d x, __m256d w) {
  const __m256d y = _mm256_sub_pd(x, w);
  const __m256d c = _mm256_andnot_pd(_mm256_cmp_pd(y, _mm256_setzero_pd(), _CMP_LT_OQ), y);
  return absv(_mm256_sub_pd(x, c));
}

/// |x − min_of(max_of(y, −t), t)|, y = x − w, t = μ·max_of(0, λ_n).
DC_AVX2 inline __m256d tangent_error(__m256d x, __m256d w, __m256d mu, __m256d ln) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d pos = _mm256_and_pd(_mm256_cmp_pd(zero, ln, _CMP_LT_OQ), ln);
  const __m256d t = _mm256_mul_pd(mu, pos);
  const __m256d y = _mm256_sub_pd(x, w);
  const __m256d nt = _mm256_xor_pd(t, _mm256_set1_pd(-0.0));
  const __m256d m1 = _mm256_blendv_pd(y, nt, _mm256_cmp_pd(y, nt, _CMP_LT_OQ));
  const __m256d c = _mm256_blendv_pd(m1, t, _mm256_cmp_pd(t, m1, _CMP_LT_OQ));
  return absv(_mm256_sub_pd(x, c));
}

/// r = max_of(r, e) where e is not NaN; nan |= lanes where it is.
DC_AVX2 inline void fold(__m256d e, __m256d& r, int& nan) {
  const __m256d isnan = _mm256_cmp_pd(e, e, _CMP_UNORD_Q);
  nan |= _mm256_movemask_pd(isnan);
  const __m256d ok = _mm256_andnot_pd(isnan, e);  // NaN → +0 (errors are ≥ +0)
  r = _mm256_blendv_pd(r, ok, _mm256_cmp_pd(r, ok, _CMP_LT_OQ));
}

DC_AVX2 inline Vel4 velocities(const double* u, const std::int32_t* la, const std::int32_t* lb) {
  Vel4 v;
  load4(u, la, v.a0, v.a1, v.a2);
  load4(u, lb, v.v0, v.v1, v.v2);
  return v;
}

/// The scalar reduction of the 4 lanes' running maxima (order-free: no lane holds a NaN).
DC_AVX2 inline void finish(__m256d r, int nan, ResidualAcc& acc) {
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, r);
  for (const double e : lanes) acc.r = max_of(acc.r, e);
  acc.nan = acc.nan || nan != 0;
}

}  // namespace

DC_AVX2 void residual_avx2(const Batch* batches, int b0, int b1, const double* lam, const double* diag,
                           const double* u, double omega, ResidualAcc& acc) {
  __m256d r = _mm256_setzero_pd();
  int nan = 0;
  const __m256d om = _mm256_set1_pd(omega);
  for (int bi = b0; bi < b1; ++bi) {
    const Batch& B = batches[bi];
    const double* x = lam + static_cast<long>(bi) * 2 * W;
    const double* d = diag + static_cast<long>(bi) * 2 * W;
    for (int h = 0; h < W; h += 4) {
      if (h >= B.count) break;  // an all-padding half: its errors are 0
      const Vel4 v = velocities(u, B.la + h, B.lb + h);
      const __m256d xn = LU(x + h);
      const __m256d wn = _mm256_div_pd(_mm256_mul_pd(scaled(B.jn, B.bn, h, v), LU(d + h)), om);
      fold(normal_error(xn, wn), r, nan);
      const __m256d wt = _mm256_div_pd(_mm256_mul_pd(scaled(B.jt, B.bt, h, v), LU(d + W + h)), om);
      fold(tangent_error(LU(x + W + h), wt, L(B.mu + h), xn), r, nan);
    }
  }
  finish(r, nan, acc);
}

DC_AVX2 void residual_pairs_avx2(const PairBatch* pairs, int b0, int b1, const double* lam, const double* diag,
                                 const double* u, double omega, ResidualAcc& acc) {
  __m256d r = _mm256_setzero_pd();
  int nan = 0;
  const __m256d om = _mm256_set1_pd(omega);
  for (int bi = b0; bi < b1; ++bi) {
    const PairBatch& P = pairs[bi];
    const double* x = lam + static_cast<long>(bi) * 4 * W;
    const double* d = diag + static_cast<long>(bi) * 4 * W;
    for (int h = 0; h < W; h += 4) {
      if (h >= P.count) break;
      const Vel4 v = velocities(u, P.la + h, P.lb + h);
      const __m256d x0 = LU(x + h), x1 = LU(x + 2 * W + h);
      fold(normal_error(x0, _mm256_mul_pd(scaled(P.jn0, P.bn0, h, v), LU(d + h))), r, nan);
      const __m256d wt0 = _mm256_div_pd(_mm256_mul_pd(scaled(P.jt0, P.bt0, h, v), LU(d + W + h)), om);
      fold(tangent_error(LU(x + W + h), wt0, L(P.mu0 + h), x0), r, nan);
      fold(normal_error(x1, _mm256_mul_pd(scaled(P.jn1, P.bn1, h, v), LU(d + 2 * W + h))), r, nan);
      const __m256d wt1 = _mm256_div_pd(_mm256_mul_pd(scaled(P.jt1, P.bt1, h, v), LU(d + 3 * W + h)), om);
      fold(tangent_error(LU(x + 3 * W + h), wt1, L(P.mu1 + h), x1), r, nan);
    }
  }
  finish(r, nan, acc);
}

}  // namespace dc::colored

#else

namespace dc::colored {
void residual_avx2(const Batch*, int, int, const double*, const double*, const double*, double, ResidualAcc&) {}
void residual_pairs_avx2(const PairBatch*, int, int, const double*, const double*, const double*, double,
                         ResidualAcc&) {}
}  // namespace dc::colored

#endif
