// The AVX-512 kernel of pgs-colored's packed closing residual (packed_residual.hpp): one batch = 8
// lanes of one zmm register per coefficient, compiled for AVX-512 F/DQ/VL by function attribute
// and chosen at run time. Per lane the operations of residual_scalar in its order, so the errors
// are the scalar kernel's bits.
#include "solvers/pgs_colored/residual/packed_residual.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#define DC_AVX512 __attribute__((target("avx512f,avx512dq,avx512vl,fma")))

namespace dc::colored {
namespace {

/// Bodies k and k + 4 of off[0..7] in one register (low and high half).
DC_AVX512 inline __m512d pair_of(const double* u, const std::int32_t* off, int k) {
  return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(u + off[k])), _mm256_loadu_pd(u + off[k + 4]), 1);
}

/// x = (v_x of the 8 lanes), y = (v_y …), w = (ω …) of the bodies at Δu offsets off[0..7]
/// (the sweep kernel's transpose, pgs_colored_avx512.cpp).
DC_AVX512 inline void load8(const double* u, const std::int32_t* off, __m512d& x, __m512d& y, __m512d& w) {
  const __m512d z0 = pair_of(u, off, 0), z1 = pair_of(u, off, 1), z2 = pair_of(u, off, 2), z3 = pair_of(u, off, 3);
  const __m512d lo01 = _mm512_unpacklo_pd(z0, z1);
  const __m512d hi01 = _mm512_unpackhi_pd(z0, z1);
  const __m512d lo23 = _mm512_unpacklo_pd(z2, z3);
  const __m512d hi23 = _mm512_unpackhi_pd(z2, z3);
  const __m512i first = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
  const __m512i second = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
  x = _mm512_permutex2var_pd(lo01, first, lo23);
  w = _mm512_permutex2var_pd(lo01, second, lo23);
  y = _mm512_permutex2var_pd(hi01, first, hi23);
}

DC_AVX512 inline __m512d L(const double* p) { return _mm512_load_pd(p); }
DC_AVX512 inline __m512d LU(const double* p) { return _mm512_loadu_pd(p); }
DC_AVX512 inline __m512d absv(__m512d x) { return _mm512_andnot_pd(_mm512_set1_pd(-0.0), x); }

struct Vel8 {
  __m512d a0, a1, a2, v0, v1, v2;
};

DC_AVX512 inline __m512d scaled(const double (*j)[W], const double* b, const Vel8& v) {
  const __m512d s0 = _mm512_fmadd_pd(L(j[0]), v.a0, _mm512_mul_pd(L(j[1]), v.a1));
  const __m512d s1 = _mm512_fmadd_pd(L(j[2]), v.a2, _mm512_mul_pd(L(j[3]), v.v0));
  const __m512d s2 = _mm512_fmadd_pd(L(j[4]), v.v1, _mm512_mul_pd(L(j[5]), v.v2));
  return _mm512_add_pd(_mm512_add_pd(L(b), s0), _mm512_add_pd(s1, s2));
}

/// |x − ((y < 0) ? +0 : y)|, y = x − w.
DC_AVX512 inline __m512d normal_error(__m512d x, __m512d w) {
  const __m512d y = _mm512_sub_pd(x, w);
  const __mmask8 neg = _mm512_cmp_pd_mask(y, _mm512_setzero_pd(), _CMP_LT_OQ);
  const __m512d c = _mm512_mask_mov_pd(y, neg, _mm512_setzero_pd());
  return absv(_mm512_sub_pd(x, c));
}

/// |x − min_of(max_of(y, −t), t)|, y = x − w, t = μ·max_of(0, λ_n).
DC_AVX512 inline __m512d tangent_error(__m512d x, __m512d w, __m512d mu, __m512d ln) {
  const __m512d zero = _mm512_setzero_pd();
  const __m512d pos = _mm512_maskz_mov_pd(_mm512_cmp_pd_mask(zero, ln, _CMP_LT_OQ), ln);
  const __m512d t = _mm512_mul_pd(mu, pos);
  const __m512d y = _mm512_sub_pd(x, w);
  const __m512d nt = _mm512_xor_pd(t, _mm512_set1_pd(-0.0));
  const __m512d m1 = _mm512_mask_mov_pd(y, _mm512_cmp_pd_mask(y, nt, _CMP_LT_OQ), nt);
  const __m512d c = _mm512_mask_mov_pd(m1, _mm512_cmp_pd_mask(t, m1, _CMP_LT_OQ), t);
  return absv(_mm512_sub_pd(x, c));
}

/// r = max_of(r, e) where e is not NaN; nan |= lanes where it is.
DC_AVX512 inline void fold(__m512d e, __m512d& r, unsigned& nan) {
  const __mmask8 isnan = _mm512_cmp_pd_mask(e, e, _CMP_UNORD_Q);
  nan |= isnan;
  const __mmask8 larger = _mm512_mask_cmp_pd_mask(static_cast<__mmask8>(~isnan), r, e, _CMP_LT_OQ);
  r = _mm512_mask_mov_pd(r, larger, e);
}

DC_AVX512 inline Vel8 velocities(const double* u, const std::int32_t* la, const std::int32_t* lb) {
  Vel8 v;
  load8(u, la, v.a0, v.a1, v.a2);
  load8(u, lb, v.v0, v.v1, v.v2);
  return v;
}

/// The scalar reduction of the 8 lanes' running maxima (order-free: no lane holds a NaN).
DC_AVX512 inline void finish(__m512d r, unsigned nan, ResidualAcc& acc) {
  alignas(64) double lanes[8];
  _mm512_store_pd(lanes, r);
  for (const double e : lanes) acc.r = max_of(acc.r, e);
  acc.nan = acc.nan || nan != 0;
}

}  // namespace

namespace {

/// scaled() of a compact batch's row (slots 0, 1, 2, 5 stored; 3, 4 = 0 − slots 0, 1 on the lanes
/// of `two`, else +0: compact_batch.hpp's expand).
DC_AVX512 inline __m512d scaled_compact(const double (*j)[W], __mmask8 two, const double* b, const Vel8& v) {
  const __m512d zero = _mm512_setzero_pd(), j0 = L(j[0]), j1 = L(j[1]);
  const __m512d j3 = _mm512_maskz_sub_pd(two, zero, j0), j4 = _mm512_maskz_sub_pd(two, zero, j1);
  const __m512d s0 = _mm512_fmadd_pd(j0, v.a0, _mm512_mul_pd(j1, v.a1));
  const __m512d s1 = _mm512_fmadd_pd(L(j[2]), v.a2, _mm512_mul_pd(j3, v.v0));
  const __m512d s2 = _mm512_fmadd_pd(j4, v.v1, _mm512_mul_pd(L(j[3]), v.v2));
  return _mm512_add_pd(_mm512_add_pd(L(b), s0), _mm512_add_pd(s1, s2));
}

}  // namespace

DC_AVX512 void residual_compact_avx512(const CompactBatch* batches, int b0, int b1, const double* lam,
                                       const double* diag, const double* u, double omega, ResidualAcc& acc) {
  __m512d r = _mm512_setzero_pd();
  unsigned nan = 0;
  const __m512d om = _mm512_set1_pd(omega);
  for (int bi = b0; bi < b1; ++bi) {
    const CompactBatch& B = batches[bi];
    const double* x = lam + static_cast<long>(bi) * 2 * W;
    const double* d = diag + static_cast<long>(bi) * 2 * W;
    const Vel8 v = velocities(u, B.la, B.lb);
    const __m512d xn = LU(x);
    fold(normal_error(xn, _mm512_div_pd(_mm512_mul_pd(scaled_compact(B.jn, B.two, B.bn, v), LU(d)), om)), r, nan);
    const __m512d wt = _mm512_div_pd(_mm512_mul_pd(scaled_compact(B.jt, B.two, B.bt, v), LU(d + W)), om);
    fold(tangent_error(LU(x + W), wt, L(B.mu), xn), r, nan);
  }
  finish(r, nan, acc);
}

DC_AVX512 void residual_avx512(const Batch* batches, int b0, int b1, const double* lam, const double* diag,
                               const double* u, double omega, ResidualAcc& acc) {
  __m512d r = _mm512_setzero_pd();
  unsigned nan = 0;
  const __m512d om = _mm512_set1_pd(omega);
  for (int bi = b0; bi < b1; ++bi) {
    const Batch& B = batches[bi];
    const double* x = lam + static_cast<long>(bi) * 2 * W;
    const double* d = diag + static_cast<long>(bi) * 2 * W;
    const Vel8 v = velocities(u, B.la, B.lb);
    const __m512d xn = LU(x);
    fold(normal_error(xn, _mm512_div_pd(_mm512_mul_pd(scaled(B.jn, B.bn, v), LU(d)), om)), r, nan);
    const __m512d wt = _mm512_div_pd(_mm512_mul_pd(scaled(B.jt, B.bt, v), LU(d + W)), om);
    fold(tangent_error(LU(x + W), wt, L(B.mu), xn), r, nan);
  }
  finish(r, nan, acc);
}

DC_AVX512 void residual_pairs_avx512(const PairBatch* pairs, int b0, int b1, const double* lam, const double* diag,
                                     const double* u, double omega, ResidualAcc& acc) {
  __m512d r = _mm512_setzero_pd();
  unsigned nan = 0;
  const __m512d om = _mm512_set1_pd(omega);
  for (int bi = b0; bi < b1; ++bi) {
    const PairBatch& P = pairs[bi];
    const double* x = lam + static_cast<long>(bi) * 4 * W;
    const double* d = diag + static_cast<long>(bi) * 4 * W;
    const Vel8 v = velocities(u, P.la, P.lb);
    const __m512d x0 = LU(x), x1 = LU(x + 2 * W);
    fold(normal_error(x0, _mm512_mul_pd(scaled(P.jn0, P.bn0, v), LU(d))), r, nan);
    const __m512d wt0 = _mm512_div_pd(_mm512_mul_pd(scaled(P.jt0, P.bt0, v), LU(d + W)), om);
    fold(tangent_error(LU(x + W), wt0, L(P.mu0), x0), r, nan);
    fold(normal_error(x1, _mm512_mul_pd(scaled(P.jn1, P.bn1, v), LU(d + 2 * W))), r, nan);
    const __m512d wt1 = _mm512_div_pd(_mm512_mul_pd(scaled(P.jt1, P.bt1, v), LU(d + 3 * W)), om);
    fold(tangent_error(LU(x + 3 * W), wt1, L(P.mu1), x1), r, nan);
  }
  finish(r, nan, acc);
}

}  // namespace dc::colored

#else

namespace dc::colored {
void residual_avx512(const Batch*, int, int, const double*, const double*, const double*, double, ResidualAcc&) {}
void residual_compact_avx512(const CompactBatch*, int, int, const double*, const double*, const double*, double,
                             ResidualAcc&) {}
void residual_pairs_avx512(const PairBatch*, int, int, const double*, const double*, const double*, double,
                           ResidualAcc&) {}
}  // namespace dc::colored

#endif
