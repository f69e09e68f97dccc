// The AVX-512 colour kernel of "pgs-colored" (pgs_colored_batch.hpp): one batch = 8 lanes of one
// zmm register per coefficient. Compiled for AVX-512 F/DQ/VL by function attribute in every
// x86-64 build and chosen at run time (cpu_has_avx512). Per lane the operations of sweep_scalar
// in its order (explicit FMAs, the same tree sums, the clamps as compare-and-select), so the
// iterates are the scalar kernel's bit for bit.
// Bodies: 8 256-bit loads transposed into 3 registers (v_x, v_y, ω), written back by the inverse
// transpose and 8 masked 256-bit stores (absent bodies masked off: no shared dummy, no false
// sharing). Hardware gathers/scatters (vgatherdpd/vscatterdpd) are not used because they are
// slower than the transposes. Bodies of one colour are distinct, so the stores never collide.
#include "solvers/pgs_colored/compact/compact_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include <cstddef>
#include <limits>

#define DC_AVX512 __attribute__((target("avx512f,avx512dq,avx512vl,fma")))

namespace dc::colored {
namespace {

/// x = (v_x of the 8 lanes), y = (v_y …), w = (ω …) of the bodies at Δu offsets off[0..7].
DC_AVX512 inline void load8(const double* u, const std::int32_t* off, __m512d& x, __m512d& y, __m512d& w) {
  const __m512d z0 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(u + off[0])), _mm256_loadu_pd(u + off[4]), 1);
  const __m512d z1 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(u + off[1])), _mm256_loadu_pd(u + off[5]), 1);
  const __m512d z2 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(u + off[2])), _mm256_loadu_pd(u + off[6]), 1);
  const __m512d z3 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(u + off[3])), _mm256_loadu_pd(u + off[7]), 1);
  const __m512d lo01 = _mm512_unpacklo_pd(z0, z1);  // x0 x1 w0 w1 | x4 x5 w4 w5
  const __m512d hi01 = _mm512_unpackhi_pd(z0, z1);  // y0 y1 p0 p1 | y4 y5 p4 p5
  const __m512d lo23 = _mm512_unpacklo_pd(z2, z3);
  const __m512d hi23 = _mm512_unpackhi_pd(z2, z3);
  const __m512i first = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13);
  const __m512i second = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
  x = _mm512_permutex2var_pd(lo01, first, lo23);
  w = _mm512_permutex2var_pd(lo01, second, lo23);
  y = _mm512_permutex2var_pd(hi01, first, hi23);
}

/// The inverse of load8: (x_k, y_k, w_k, 0) to u + off[k] where keep[k] ≠ 0.
DC_AVX512 inline void store8(double* u, const std::int32_t* off, const std::uint8_t* keep, __m512d x, __m512d y,
                             __m512d w) {
  const __m512d zero = _mm512_setzero_pd();
  const __m512d t0 = _mm512_unpacklo_pd(x, y);     // x0 y0 | x2 y2 | x4 y4 | x6 y6
  const __m512d t1 = _mm512_unpackhi_pd(x, y);     // x1 y1 | x3 y3 | …
  const __m512d t2 = _mm512_unpacklo_pd(w, zero);  // w0 0 | w2 0 | …
  const __m512d t3 = _mm512_unpackhi_pd(w, zero);  // w1 0 | w3 0 | …
  const __m512i lo = _mm512_setr_epi64(0, 1, 8, 9, 2, 3, 10, 11);
  const __m512i hi = _mm512_setr_epi64(4, 5, 12, 13, 6, 7, 14, 15);
  const __m512d r02 = _mm512_permutex2var_pd(t0, lo, t2);  // body 0 | body 2
  const __m512d r46 = _mm512_permutex2var_pd(t0, hi, t2);
  const __m512d r13 = _mm512_permutex2var_pd(t1, lo, t3);
  const __m512d r57 = _mm512_permutex2var_pd(t1, hi, t3);
  auto mask = [keep](int k) { return static_cast<__mmask8>(keep[k] ? 0xF : 0); };
  _mm256_mask_storeu_pd(u + off[0], mask(0), _mm512_castpd512_pd256(r02));
  _mm256_mask_storeu_pd(u + off[2], mask(2), _mm512_extractf64x4_pd(r02, 1));
  _mm256_mask_storeu_pd(u + off[1], mask(1), _mm512_castpd512_pd256(r13));
  _mm256_mask_storeu_pd(u + off[3], mask(3), _mm512_extractf64x4_pd(r13, 1));
  _mm256_mask_storeu_pd(u + off[4], mask(4), _mm512_castpd512_pd256(r46));
  _mm256_mask_storeu_pd(u + off[6], mask(6), _mm512_extractf64x4_pd(r46, 1));
  _mm256_mask_storeu_pd(u + off[5], mask(5), _mm512_castpd512_pd256(r57));
  _mm256_mask_storeu_pd(u + off[7], mask(7), _mm512_extractf64x4_pd(r57, 1));
}

DC_AVX512 inline __m512d L(const double* p) { return _mm512_load_pd(p); }
/// λ lives in Eigen vectors, aligned to EIGEN_MAX_ALIGN_BYTES only (16 bytes in a portable build,
/// where this kernel is chosen at run time too): unaligned access, free on aligned data.
DC_AVX512 inline __m512d LU(const double* p) { return _mm512_loadu_pd(p); }
DC_AVX512 inline __m512d absv(__m512d x) { return _mm512_andnot_pd(_mm512_set1_pd(-0.0), x); }
/// Lanes where |x| is not < ∞ (±∞ or NaN).
DC_AVX512 inline __mmask8 nonfinite(__m512d x) {
  return _mm512_cmp_pd_mask(absv(x), _mm512_set1_pd(std::numeric_limits<double>::infinity()), _CMP_NLT_UQ);
}

DC_AVX512 inline __m512d residual(const double (*j)[W], const double* b, __m512d a0, __m512d a1, __m512d a2,
                                  __m512d v0, __m512d v1, __m512d v2) {
  const __m512d s0 = _mm512_fmadd_pd(L(j[0]), a0, _mm512_mul_pd(L(j[1]), a1));
  const __m512d s1 = _mm512_fmadd_pd(L(j[2]), a2, _mm512_mul_pd(L(j[3]), v0));
  const __m512d s2 = _mm512_fmadd_pd(L(j[4]), v1, _mm512_mul_pd(L(j[5]), v2));
  return _mm512_add_pd(_mm512_add_pd(L(b), s0), _mm512_add_pd(s1, s2));
}

DC_AVX512 inline void update(const double (*mj)[W], __m512d d, __m512d& a0, __m512d& a1, __m512d& a2, __m512d& v0,
                             __m512d& v1, __m512d& v2) {
  a0 = _mm512_fmadd_pd(L(mj[0]), d, a0);
  a1 = _mm512_fmadd_pd(L(mj[1]), d, a1);
  a2 = _mm512_fmadd_pd(L(mj[2]), d, a2);
  v0 = _mm512_fmadd_pd(L(mj[3]), d, v0);
  v1 = _mm512_fmadd_pd(L(mj[4]), d, v1);
  v2 = _mm512_fmadd_pd(L(mj[5]), d, v2);
}

/// Lanes where x ≥ 0 (false for NaN), as the scalar kernel's x >= 0.0.
DC_AVX512 inline __mmask8 ge0(__m512d x) { return _mm512_cmp_pd_mask(x, _mm512_setzero_pd(), _CMP_GE_OQ); }

/// A pair batch's tangent row (sweep_pairs_scalar's pair_tangent on 8 lanes); returns the new λ_t.
DC_AVX512 inline __m512d pair_tangent(const double (*jt)[W], const double (*mjt)[W], const double* bt,
                                      const double* mu, __m512d ln, __m512d old, __m512d& a0, __m512d& a1,
                                      __m512d& a2, __m512d& v0, __m512d& v1, __m512d& v2, __m512d& theta,
                                      __mmask8& bad) {
  const __m512d zero = _mm512_setzero_pd(), sign = _mm512_set1_pd(-0.0);
  const __m512d res = residual(jt, bt, a0, a1, a2, v0, v1, v2);
  const __m512d pos = _mm512_mask_mov_pd(zero, _mm512_cmp_pd_mask(zero, ln, _CMP_LT_OQ), ln);
  const __m512d t = _mm512_mul_pd(L(mu), pos);
  const __m512d y = _mm512_sub_pd(old, res);
  const __m512d nt = _mm512_xor_pd(t, sign);
  const __m512d m1 = _mm512_mask_mov_pd(y, _mm512_cmp_pd_mask(y, nt, _CMP_LT_OQ), nt);
  const __m512d c = _mm512_mask_mov_pd(m1, _mm512_cmp_pd_mask(t, m1, _CMP_LT_OQ), t);
  const __mmask8 active = _mm512_cmp_pd_mask(zero, t, _CMP_LT_OQ);
  const __m512d x = _mm512_mask_mov_pd(zero, active, c);
  bad |= nonfinite(_mm512_mask_mov_pd(y, active, x));
  update(mjt, _mm512_sub_pd(x, old), a0, a1, a2, v0, v1, v2);
  theta = _mm512_max_pd(theta, absv(_mm512_sub_pd(x, old)));
  return x;
}

/// One pair batch (λ at lin/lout + 32·bi): sweep_pairs_scalar's operations on 8 lanes.
DC_AVX512 inline void pair_batch(const PairBatch& P, const double* lin, double* lout, double* u, __m512d& theta,
                                 __mmask8& bad) {
  const __m512d zero = _mm512_setzero_pd();
  __m512d a0, a1, a2, v0, v1, v2;
  load8(u, P.la, a0, a1, a2);
  load8(u, P.lb, v0, v1, v2);
  const __m512d l0 = LU(lin), l1 = LU(lin + 2 * W);
  _mm512_storeu_pd(lout + W, pair_tangent(P.jt0, P.mjt0, P.bt0, P.mu0, l0, LU(lin + W), a0, a1, a2, v0, v1, v2,
                                          theta, bad));
  _mm512_storeu_pd(lout + 3 * W, pair_tangent(P.jt1, P.mjt1, P.bt1, P.mu1, l1, LU(lin + 3 * W), a0, a1, a2, v0, v1,
                                              v2, theta, bad));
  const __m512d res0 = residual(P.jn0, P.bn0, a0, a1, a2, v0, v1, v2);
  const __m512d res1 = residual(P.jn1, P.bn1, a0, a1, a2, v0, v1, v2);
  const __m512d c01 = L(P.c01), c10 = L(P.c10), inv_det = L(P.inv_det);
  const __m512d beta0 = _mm512_sub_pd(_mm512_sub_pd(res0, l0), _mm512_mul_pd(c01, l1));
  const __m512d beta1 = _mm512_sub_pd(_mm512_sub_pd(res1, l1), _mm512_mul_pd(c10, l0));
  const __m512d both0 = _mm512_mul_pd(_mm512_sub_pd(_mm512_mul_pd(c01, beta1), beta0), inv_det);
  const __m512d both1 = _mm512_mul_pd(_mm512_sub_pd(_mm512_mul_pd(c10, beta0), beta1), inv_det);
  const __m512d sign = _mm512_set1_pd(-0.0);
  const __m512d nb0 = _mm512_xor_pd(beta0, sign), nb1 = _mm512_xor_pd(beta1, sign);
  const __m512d y0 = _mm512_sub_pd(l0, res0);
  const __m512d f0 = _mm512_mask_mov_pd(y0, _mm512_cmp_pd_mask(y0, zero, _CMP_LT_OQ), zero);
  const __m512d y1 = _mm512_sub_pd(l1, _mm512_add_pd(res1, _mm512_mul_pd(c10, _mm512_sub_pd(f0, l0))));
  const __m512d f1 = _mm512_mask_mov_pd(y1, _mm512_cmp_pd_mask(y1, zero, _CMP_LT_OQ), zero);
  const __mmask8 blk = _mm512_cmp_pd_mask(zero, L(P.block), _CMP_LT_OQ);
  const __mmask8 case1 = blk & ge0(both0) & ge0(both1);
  const __mmask8 case2 = blk & ge0(nb0) & ge0(_mm512_add_pd(_mm512_mul_pd(c10, nb0), beta1));
  const __mmask8 case3 = blk & ge0(nb1) & ge0(_mm512_add_pd(_mm512_mul_pd(c01, nb1), beta0));
  const __mmask8 case4 = blk & ge0(beta0) & ge0(beta1);
  __m512d x0 = _mm512_mask_mov_pd(f0, static_cast<__mmask8>(case3 | case4), zero);
  x0 = _mm512_mask_mov_pd(x0, case2, nb0);
  x0 = _mm512_mask_mov_pd(x0, case1, both0);
  __m512d x1 = _mm512_mask_mov_pd(f1, case4, zero);
  x1 = _mm512_mask_mov_pd(x1, case3, nb1);
  x1 = _mm512_mask_mov_pd(x1, case2, zero);
  x1 = _mm512_mask_mov_pd(x1, case1, both1);
  bad |= nonfinite(x0) | nonfinite(x1);
  const __m512d d0 = _mm512_sub_pd(x0, l0), d1 = _mm512_sub_pd(x1, l1);
  _mm512_storeu_pd(lout, x0);
  _mm512_storeu_pd(lout + 2 * W, x1);
  update(P.mjn0, d0, a0, a1, a2, v0, v1, v2);
  update(P.mjn1, d1, a0, a1, a2, v0, v1, v2);
  theta = _mm512_max_pd(theta, absv(d0));
  theta = _mm512_max_pd(theta, absv(d1));
  const __m512d z = _mm512_add_pd(
      _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(a0, zero), _mm512_mul_pd(a1, zero)),
                    _mm512_add_pd(_mm512_mul_pd(a2, zero), _mm512_mul_pd(v0, zero))),
      _mm512_add_pd(_mm512_mul_pd(v1, zero), _mm512_mul_pd(v2, zero)));
  bad |= _mm512_cmp_pd_mask(z, z, _CMP_UNORD_Q);
  store8(u, P.la, P.ka, a0, a1, a2);
  store8(u, P.lb, P.kb, v0, v1, v2);
}

/// max_of over the 8 lanes of θ, into acc (by hand: GCC 12 warns about an uninitialised
/// temporary inside _mm512_reduce_max_pd; θ ≥ 0, so the order does not matter).
DC_AVX512 inline void reduce(__m512d theta, __mmask8 bad, Acc& acc) {
  alignas(64) double lanes[W];
  _mm512_store_pd(lanes, theta);
  double m = lanes[0];
  for (int k = 1; k < W; ++k) m = max_of(m, lanes[k]);
  acc.theta = max_of(acc.theta, m);
  acc.bad = acc.bad || bad != 0;
}

}  // namespace

DC_AVX512 void sweep_pairs_avx512(const PairBatch* __restrict pairs, int b0, int b1, const double* __restrict in,
                                  double* __restrict out, double* __restrict u, Acc& acc) {
  __m512d theta = _mm512_set1_pd(acc.theta);
  __mmask8 bad = 0;
  for (int bi = b0; bi < b1; ++bi)
    pair_batch(pairs[bi], in + static_cast<long>(bi) * 4 * W, out + static_cast<long>(bi) * 4 * W, u, theta, bad);
  reduce(theta, bad, acc);
}

namespace {

/// The 6 coefficients of one row on 8 lanes, in slot order.
struct Row6 {
  __m512d c[6];
};

DC_AVX512 inline __m512d residual(const Row6& j, const double* b, __m512d a0, __m512d a1, __m512d a2, __m512d v0,
                                  __m512d v1, __m512d v2) {
  const __m512d s0 = _mm512_fmadd_pd(j.c[0], a0, _mm512_mul_pd(j.c[1], a1));
  const __m512d s1 = _mm512_fmadd_pd(j.c[2], a2, _mm512_mul_pd(j.c[3], v0));
  const __m512d s2 = _mm512_fmadd_pd(j.c[4], v1, _mm512_mul_pd(j.c[5], v2));
  return _mm512_add_pd(_mm512_add_pd(L(b), s0), _mm512_add_pd(s1, s2));
}

DC_AVX512 inline void update(const Row6& mj, __m512d d, __m512d& a0, __m512d& a1, __m512d& a2, __m512d& v0,
                             __m512d& v1, __m512d& v2) {
  a0 = _mm512_fmadd_pd(mj.c[0], d, a0);
  a1 = _mm512_fmadd_pd(mj.c[1], d, a1);
  a2 = _mm512_fmadd_pd(mj.c[2], d, a2);
  v0 = _mm512_fmadd_pd(mj.c[3], d, v0);
  v1 = _mm512_fmadd_pd(mj.c[4], d, v1);
  v2 = _mm512_fmadd_pd(mj.c[5], d, v2);
}

/// A Batch's rows as they are stored.
struct FullRows {
  const Batch& B;
  DC_AVX512 static Row6 load(const double (*j)[W]) { return {{L(j[0]), L(j[1]), L(j[2]), L(j[3]), L(j[4]), L(j[5])}}; }
  DC_AVX512 Row6 jn() const { return load(B.jn); }
  DC_AVX512 Row6 mjn() const { return load(B.mjn); }
  DC_AVX512 Row6 jt() const { return load(B.jt); }
  DC_AVX512 Row6 mjt() const { return load(B.mjt); }
};

/// A CompactBatch's rows, the derived coefficients formed in registers as expand() forms them
/// (compact_batch.hpp): 0 − x where the lane's bit is set, +0 elsewhere.
struct CompactRows {
  const CompactBatch& C;
  DC_AVX512 Row6 j(const double (*k)[W]) const {
    const __m512d zero = _mm512_setzero_pd(), c0 = L(k[0]), c1 = L(k[1]);
    return {{c0, c1, L(k[2]), _mm512_maskz_sub_pd(C.two, zero, c0), _mm512_maskz_sub_pd(C.two, zero, c1), L(k[3])}};
  }
  DC_AVX512 Row6 jn() const { return j(C.jn); }
  DC_AVX512 Row6 jt() const { return j(C.jt); }
  DC_AVX512 Row6 mjn() const {
    return {{L(C.mjn[0]), L(C.mjn[1]), L(C.mjn[2]), L(C.mjn[3]), L(C.mjn[4]), L(C.mjn[5])}};
  }
  DC_AVX512 Row6 mjt() const {
    const __m512d zero = _mm512_setzero_pd();
    return {{_mm512_maskz_sub_pd(C.fric, zero, L(C.mjn[1])), _mm512_maskz_mov_pd(C.fric, L(C.mjn[0])), L(C.mjt[0]),
             _mm512_maskz_sub_pd(C.fric, zero, L(C.mjn[4])), _mm512_maskz_mov_pd(C.fric, L(C.mjn[3])), L(C.mjt[1])}};
  }
};

/// One batch (λ at lin/lout; B: a Batch or CompactBatch, R its rows): sweep_scalar's operations
/// on 8 lanes.
template <class BatchT, class Rows>
DC_AVX512 inline void single_batch(const BatchT& B, const Rows& R, const double* __restrict lin,
                                   double* __restrict lout, double* __restrict u, __m512d& theta, __mmask8& bad) {
  const __m512d zero = _mm512_setzero_pd();
  const __m512d sign = _mm512_set1_pd(-0.0);
  {
    __m512d a0, a1, a2, v0, v1, v2;
    load8(u, B.la, a0, a1, a2);
    load8(u, B.lb, v0, v1, v2);
    __m512d xn;
    {
      const __m512d res = residual(R.jn(), B.bn, a0, a1, a2, v0, v1, v2);
      const __m512d old = LU(lin);
      const __m512d y = _mm512_sub_pd(old, res);
      xn = _mm512_mask_mov_pd(y, _mm512_cmp_pd_mask(y, zero, _CMP_LT_OQ), zero);  // (y < 0) ? 0 : y
      bad |= nonfinite(xn);
      const __m512d d = _mm512_sub_pd(xn, old);
      _mm512_storeu_pd(lout, xn);
      update(R.mjn(), d, a0, a1, a2, v0, v1, v2);
      theta = _mm512_max_pd(theta, absv(d));
    }
    {
      const __m512d res = residual(R.jt(), B.bt, a0, a1, a2, v0, v1, v2);
      const __m512d old = LU(lin + W);
      // t = μ · max_of(0, λ_n) = μ · ((0 < λ_n) ? λ_n : 0)
      const __m512d pos = _mm512_mask_mov_pd(zero, _mm512_cmp_pd_mask(zero, xn, _CMP_LT_OQ), xn);
      const __m512d t = _mm512_mul_pd(L(B.mu), pos);
      const __m512d y = _mm512_sub_pd(old, res);
      const __m512d nt = _mm512_xor_pd(t, sign);
      const __m512d m1 = _mm512_mask_mov_pd(y, _mm512_cmp_pd_mask(y, nt, _CMP_LT_OQ), nt);  // max_of(y, −t)
      const __m512d c = _mm512_mask_mov_pd(m1, _mm512_cmp_pd_mask(t, m1, _CMP_LT_OQ), t);  // min_of(·, t)
      const __mmask8 active = _mm512_cmp_pd_mask(zero, t, _CMP_LT_OQ);
      const __m512d x = _mm512_mask_mov_pd(zero, active, c);
      bad |= nonfinite(_mm512_mask_mov_pd(y, active, x));
      const __m512d d = _mm512_sub_pd(x, old);
      _mm512_storeu_pd(lout + W, x);
      update(R.mjt(), d, a0, a1, a2, v0, v1, v2);
      theta = _mm512_max_pd(theta, absv(d));
    }
    // Δu check fused into the sweep: Σ x·0 is NaN exactly when a velocity is not finite.
    const __m512d z = _mm512_add_pd(
        _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(a0, zero), _mm512_mul_pd(a1, zero)),
                      _mm512_add_pd(_mm512_mul_pd(a2, zero), _mm512_mul_pd(v0, zero))),
        _mm512_add_pd(_mm512_mul_pd(v1, zero), _mm512_mul_pd(v2, zero)));
    bad |= _mm512_cmp_pd_mask(z, z, _CMP_UNORD_Q);
    store8(u, B.la, B.ka, a0, a1, a2);
    store8(u, B.lb, B.kb, v0, v1, v2);
  }
}

}  // namespace

DC_AVX512 void sweep_avx512(const Batch* __restrict batches, int b0, int b1, const double* __restrict in,
                            double* __restrict out, double* __restrict u, Acc& acc) {
  __m512d theta = _mm512_set1_pd(acc.theta);
  __mmask8 bad = 0;
  for (int bi = b0; bi < b1; ++bi)
    single_batch(batches[bi], FullRows{batches[bi]}, in + static_cast<long>(bi) * 2 * W,
                 out + static_cast<long>(bi) * 2 * W, u, theta, bad);
  reduce(theta, bad, acc);
}

namespace {

/// Batches a compact sweep prefetches ahead. The compact layout is taken for packed problems
/// larger than the L2 cache, whose batches (21 lines each) and λ each sweep streams from L3:
/// requesting batch bi + kAhead while batch bi is swept overlaps their L3 latency with the
/// sweep, and the Δu of the next batch's bodies (scattered lines that no hardware prefetcher
/// predicts) arrive while this batch is swept.
constexpr int kAhead = 4;

/// Requests batch bi + kAhead (coefficients, λ in and out) and the Δu entries of the bodies of
/// batch bi + 1 (whose indices are in cache by then: requested kAhead − 1 batches ago), where
/// they are in [b0, b1). Prefetches only: no value read or written changes.
DC_AVX512 inline void prefetch_ahead(const CompactBatch* batches, int bi, int b1, const double* in, const double* out,
                                     const double* u) {
  if (bi + kAhead < b1) {
    const char* q = reinterpret_cast<const char*>(batches + bi + kAhead);
    for (std::size_t l = 0; l < sizeof(CompactBatch); l += 64) _mm_prefetch(q + l, _MM_HINT_T0);
    const long s = static_cast<long>(bi + kAhead) * 2 * W;  // 2·W λ = two lines
    _mm_prefetch(reinterpret_cast<const char*>(in + s), _MM_HINT_T0);
    _mm_prefetch(reinterpret_cast<const char*>(in + s + W), _MM_HINT_T0);
    _mm_prefetch(reinterpret_cast<const char*>(out + s), _MM_HINT_T0);
    _mm_prefetch(reinterpret_cast<const char*>(out + s + W), _MM_HINT_T0);
  }
  if (bi + 1 < b1) {
    const CompactBatch& next = batches[bi + 1];
    for (int k = 0; k < W; ++k) {
      _mm_prefetch(reinterpret_cast<const char*>(u + next.la[k]), _MM_HINT_T0);
      _mm_prefetch(reinterpret_cast<const char*>(u + next.lb[k]), _MM_HINT_T0);
    }
  }
}

}  // namespace

DC_AVX512 void sweep_compact_avx512(const CompactBatch* __restrict batches, int b0, int b1,
                                    const double* __restrict in, double* __restrict out, double* __restrict u,
                                    Acc& acc) {
  __m512d theta = _mm512_set1_pd(acc.theta);
  __mmask8 bad = 0;
  for (int bi = b0; bi < b1; ++bi) {
    prefetch_ahead(batches, bi, b1, in, out, u);
    single_batch(batches[bi], CompactRows{batches[bi]}, in + static_cast<long>(bi) * 2 * W,
                 out + static_cast<long>(bi) * 2 * W, u, theta, bad);
  }
  reduce(theta, bad, acc);
}

bool cpu_has_avx512() {
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("fma");
}

}  // namespace dc::colored

#else

namespace dc::colored {
void sweep_avx512(const Batch*, int, int, const double*, double*, double*, Acc&) {}
void sweep_pairs_avx512(const PairBatch*, int, int, const double*, double*, double*, Acc&) {}
void sweep_compact_avx512(const CompactBatch*, int, int, const double*, double*, double*, Acc&) {}
bool cpu_has_avx512() { return false; }
}  // namespace dc::colored

#endif
