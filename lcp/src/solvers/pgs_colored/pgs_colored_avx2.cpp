// The AVX2 colour kernel of "pgs-colored" (pgs_colored_batch.hpp): a batch of 8 contacts as two
// groups of 4 lanes (__m256d), compiled for AVX2 + FMA by function attribute in every x86-64
// build and chosen at run time (cpu_has_avx2), so a portable build and a CPU without AVX-512 get
// it too. Per lane the operations of sweep_scalar, in its order: explicit FMAs, the same tree
// sums, the clamps as compare-and-select ((y < 0) ? 0 : y is andnot(y < 0, y): +0 or y, as the
// scalar select), so the iterates are the scalar kernel's bit for bit.
//
// Bodies: 4 aligned 256-bit loads of (v_x, v_y, ω, 0) and a 4 × 4 transpose (4 unpacks, 3
// lane permutes), written back by the inverse transpose and a store per lane whose body is
// written (ka/kb: a predictable branch; vmaskmovpd stores are slow on AMD cores).
#include "solvers/pgs_colored/compact/compact_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <cpuid.h>
#include <immintrin.h>

#include <limits>
#include <type_traits>

#define DC_AVX2 __attribute__((target("avx2,fma")))

namespace dc::colored {
namespace {

/// x = (v_x of lanes 0–3), y = (v_y …), w = (ω …) of the bodies at Δu offsets off[0..3].
DC_AVX2 inline void load4(const double* u, const std::int32_t* off, __m256d& x, __m256d& y, __m256d& w) {
  const __m256d r0 = _mm256_loadu_pd(u + off[0]), r1 = _mm256_loadu_pd(u + off[1]);
  const __m256d r2 = _mm256_loadu_pd(u + off[2]), r3 = _mm256_loadu_pd(u + off[3]);
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1);  // x0 x1 | w0 w1
  const __m256d t1 = _mm256_unpackhi_pd(r0, r1);  // y0 y1 | p0 p1
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3);  // x2 x3 | w2 w3
  const __m256d t3 = _mm256_unpackhi_pd(r2, r3);
  x = _mm256_permute2f128_pd(t0, t2, 0x20);
  w = _mm256_permute2f128_pd(t0, t2, 0x31);
  y = _mm256_permute2f128_pd(t1, t3, 0x20);
}

/// The inverse of load4: (x_k, y_k, w_k, 0) to u + off[k] where keep[k] ≠ 0.
DC_AVX2 inline void store4(double* u, const std::int32_t* off, const std::uint8_t* keep, __m256d x, __m256d y,
                           __m256d w) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d t0 = _mm256_unpacklo_pd(x, y);     // x0 y0 | x2 y2
  const __m256d t1 = _mm256_unpackhi_pd(x, y);     // x1 y1 | x3 y3
  const __m256d t2 = _mm256_unpacklo_pd(w, zero);  // w0 0 | w2 0
  const __m256d t3 = _mm256_unpackhi_pd(w, zero);  // w1 0 | w3 0
  if (keep[0]) _mm256_storeu_pd(u + off[0], _mm256_permute2f128_pd(t0, t2, 0x20));
  if (keep[1]) _mm256_storeu_pd(u + off[1], _mm256_permute2f128_pd(t1, t3, 0x20));
  if (keep[2]) _mm256_storeu_pd(u + off[2], _mm256_permute2f128_pd(t0, t2, 0x31));
  if (keep[3]) _mm256_storeu_pd(u + off[3], _mm256_permute2f128_pd(t1, t3, 0x31));
}

DC_AVX2 inline __m256d L(const double* p) { return _mm256_load_pd(p); }

/// λ lives in Eigen vectors, which are aligned to EIGEN_MAX_ALIGN_BYTES only: 16 bytes in a
/// portable (SSE2) build, where this kernel is chosen at run time too. Unaligned access costs
/// nothing on aligned data, so λ is read and written with loadu/storeu; the batch is alignas(64).
DC_AVX2 inline __m256d LU(const double* p) { return _mm256_loadu_pd(p); }

/// Lanes where |x| is not < ∞ (±∞ or NaN), as a 4-bit mask.
DC_AVX2 inline int nonfinite(__m256d x) {
  const __m256d sign = _mm256_set1_pd(-0.0), inf = _mm256_set1_pd(std::numeric_limits<double>::infinity());
  return _mm256_movemask_pd(_mm256_cmp_pd(_mm256_andnot_pd(sign, x), inf, _CMP_NLT_UQ));
}

/// One row's residual (b + fma(j0,a0,j1·a1)) + (fma(j2,a2,j3·v0) + fma(j4,v1,j5·v2)) on lanes h..h+3.
DC_AVX2 inline __m256d residual(const double (*j)[W], const double* b, int h, __m256d a0, __m256d a1, __m256d a2,
                                __m256d v0, __m256d v1, __m256d v2) {
  const __m256d s0 = _mm256_fmadd_pd(L(j[0] + h), a0, _mm256_mul_pd(L(j[1] + h), a1));
  const __m256d s1 = _mm256_fmadd_pd(L(j[2] + h), a2, _mm256_mul_pd(L(j[3] + h), v0));
  const __m256d s2 = _mm256_fmadd_pd(L(j[4] + h), v1, _mm256_mul_pd(L(j[5] + h), v2));
  return _mm256_add_pd(_mm256_add_pd(L(b + h), s0), _mm256_add_pd(s1, s2));
}

/// Δu += (M⁻¹ J_iᵀ Δt)·d on the 6 slots.
DC_AVX2 inline void update(const double (*mj)[W], int h, __m256d d, __m256d& a0, __m256d& a1, __m256d& a2,
                           __m256d& v0, __m256d& v1, __m256d& v2) {
  a0 = _mm256_fmadd_pd(L(mj[0] + h), d, a0);
  a1 = _mm256_fmadd_pd(L(mj[1] + h), d, a1);
  a2 = _mm256_fmadd_pd(L(mj[2] + h), d, a2);
  v0 = _mm256_fmadd_pd(L(mj[3] + h), d, v0);
  v1 = _mm256_fmadd_pd(L(mj[4] + h), d, v1);
  v2 = _mm256_fmadd_pd(L(mj[5] + h), d, v2);
}

/// The 6 coefficients of one row on 4 lanes, in slot order.
struct Row6 {
  __m256d c[6];
};

DC_AVX2 inline __m256d residual(const Row6& j, const double* b, int h, __m256d a0, __m256d a1, __m256d a2,
                                __m256d v0, __m256d v1, __m256d v2) {
  const __m256d s0 = _mm256_fmadd_pd(j.c[0], a0, _mm256_mul_pd(j.c[1], a1));
  const __m256d s1 = _mm256_fmadd_pd(j.c[2], a2, _mm256_mul_pd(j.c[3], v0));
  const __m256d s2 = _mm256_fmadd_pd(j.c[4], v1, _mm256_mul_pd(j.c[5], v2));
  return _mm256_add_pd(_mm256_add_pd(L(b + h), s0), _mm256_add_pd(s1, s2));
}

DC_AVX2 inline void update(const Row6& mj, int /*h*/, __m256d d, __m256d& a0, __m256d& a1, __m256d& a2, __m256d& v0,
                           __m256d& v1, __m256d& v2) {
  a0 = _mm256_fmadd_pd(mj.c[0], d, a0);
  a1 = _mm256_fmadd_pd(mj.c[1], d, a1);
  a2 = _mm256_fmadd_pd(mj.c[2], d, a2);
  v0 = _mm256_fmadd_pd(mj.c[3], d, v0);
  v1 = _mm256_fmadd_pd(mj.c[4], d, v1);
  v2 = _mm256_fmadd_pd(mj.c[5], d, v2);
}

/// A Batch's rows as they are stored (read through the pointer overloads of residual/update).
struct FullRows {
  const Batch& B;
  int h;
  [[nodiscard]] const double (*jn() const)[W] { return B.jn; }
  [[nodiscard]] const double (*mjn() const)[W] { return B.mjn; }
  [[nodiscard]] const double (*jt() const)[W] { return B.jt; }
  [[nodiscard]] const double (*mjt() const)[W] { return B.mjt; }
};

/// All ones on the lanes h..h+3 whose bit is set in `bits`, zeros elsewhere.
DC_AVX2 inline __m256d lane_mask(unsigned bits, int h) {
  const __m256i sel = _mm256_setr_epi64x(1, 2, 4, 8);
  const __m256i b = _mm256_and_si256(_mm256_set1_epi64x(static_cast<long long>((bits >> h) & 0xFu)), sel);
  return _mm256_castsi256_pd(_mm256_cmpeq_epi64(b, sel));
}

/// A CompactBatch's rows on lanes h..h+3, the derived coefficients formed in registers as
/// expand() forms them (compact_batch.hpp): 0 − x where the lane's bit is set, +0 elsewhere.
struct CompactRows {
  const CompactBatch& C;
  int h;
  __m256d two, fric;
  DC_AVX2 CompactRows(const CompactBatch& c, int half)
      : C(c), h(half), two(lane_mask(c.two, half)), fric(lane_mask(c.fric, half)) {}
  DC_AVX2 Row6 j(const double (*k)[W]) const {
    const __m256d zero = _mm256_setzero_pd(), c0 = L(k[0] + h), c1 = L(k[1] + h);
    return {{c0, c1, L(k[2] + h), _mm256_and_pd(_mm256_sub_pd(zero, c0), two),
             _mm256_and_pd(_mm256_sub_pd(zero, c1), two), L(k[3] + h)}};
  }
  DC_AVX2 Row6 jn() const { return j(C.jn); }
  DC_AVX2 Row6 jt() const { return j(C.jt); }
  DC_AVX2 Row6 mjn() const {
    return {{L(C.mjn[0] + h), L(C.mjn[1] + h), L(C.mjn[2] + h), L(C.mjn[3] + h), L(C.mjn[4] + h), L(C.mjn[5] + h)}};
  }
  DC_AVX2 Row6 mjt() const {
    const __m256d zero = _mm256_setzero_pd();
    return {{_mm256_and_pd(_mm256_sub_pd(zero, L(C.mjn[1] + h)), fric), _mm256_and_pd(L(C.mjn[0] + h), fric),
             L(C.mjt[0] + h), _mm256_and_pd(_mm256_sub_pd(zero, L(C.mjn[4] + h)), fric),
             _mm256_and_pd(L(C.mjn[3] + h), fric), L(C.mjt[1] + h)}};
  }
};

/// Lanes h..h+3 of batch B (a Batch or CompactBatch, R its rows on those lanes; λ at in/out + 16·bi).
template <class BatchT, class Rows>
DC_AVX2 inline void half(const BatchT& B, const Rows& R, int h, const double* lin, double* lout, double* u,
                         __m256d& theta, int& bad) {
  const __m256d zero = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.0);
  __m256d a0, a1, a2, v0, v1, v2;
  load4(u, B.la + h, a0, a1, a2);
  load4(u, B.lb + h, v0, v1, v2);
  __m256d xn;
  {
    const __m256d res = residual(R.jn(), B.bn, h, a0, a1, a2, v0, v1, v2);
    const __m256d old = LU(lin + h);
    const __m256d y = _mm256_sub_pd(old, res);
    xn = _mm256_andnot_pd(_mm256_cmp_pd(y, zero, _CMP_LT_OQ), y);  // (y < 0) ? +0 : y
    bad |= nonfinite(xn);
    const __m256d d = _mm256_sub_pd(xn, old);
    _mm256_storeu_pd(lout + h, xn);
    update(R.mjn(), h, d, a0, a1, a2, v0, v1, v2);
    theta = _mm256_max_pd(theta, _mm256_andnot_pd(sign, d));
  }
  {
    const __m256d res = residual(R.jt(), B.bt, h, a0, a1, a2, v0, v1, v2);
    const __m256d old = LU(lin + W + h);
    const __m256d pos = _mm256_and_pd(_mm256_cmp_pd(zero, xn, _CMP_LT_OQ), xn);  // (0 < λ_n) ? λ_n : +0
    const __m256d t = _mm256_mul_pd(L(B.mu + h), pos);
    const __m256d y = _mm256_sub_pd(old, res);
    const __m256d nt = _mm256_xor_pd(t, sign);
    const __m256d m1 = _mm256_blendv_pd(y, nt, _mm256_cmp_pd(y, nt, _CMP_LT_OQ));  // max_of(y, −t)
    const __m256d c = _mm256_blendv_pd(m1, t, _mm256_cmp_pd(t, m1, _CMP_LT_OQ));   // min_of(·, t)
    const __m256d active = _mm256_cmp_pd(zero, t, _CMP_LT_OQ);
    const __m256d x = _mm256_and_pd(active, c);  // active ? c : +0
    bad |= nonfinite(_mm256_blendv_pd(y, x, active));
    const __m256d d = _mm256_sub_pd(x, old);
    _mm256_storeu_pd(lout + W + h, x);
    update(R.mjt(), h, d, a0, a1, a2, v0, v1, v2);
    theta = _mm256_max_pd(theta, _mm256_andnot_pd(sign, d));
  }
  // Δu check fused into the sweep: Σ x·0 is NaN exactly when a velocity is not finite.
  const __m256d z = _mm256_add_pd(
      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a0, zero), _mm256_mul_pd(a1, zero)),
                    _mm256_add_pd(_mm256_mul_pd(a2, zero), _mm256_mul_pd(v0, zero))),
      _mm256_add_pd(_mm256_mul_pd(v1, zero), _mm256_mul_pd(v2, zero)));
  bad |= _mm256_movemask_pd(_mm256_cmp_pd(z, z, _CMP_UNORD_Q));
  store4(u, B.la + h, B.ka + h, a0, a1, a2);
  store4(u, B.lb + h, B.kb + h, v0, v1, v2);
}

/// Lanes where x ≥ 0 (false for NaN), as the scalar kernel's x >= 0.0.
DC_AVX2 inline __m256d ge0(__m256d x) { return _mm256_cmp_pd(x, _mm256_setzero_pd(), _CMP_GE_OQ); }

/// A pair lane group's tangent row (sweep_pairs_scalar's pair_tangent on lanes h..h+3).
DC_AVX2 inline __m256d pair_tangent(const double (*jt)[W], const double (*mjt)[W], const double* bt, const double* mu,
                                    int h, __m256d ln, __m256d old, __m256d& a0, __m256d& a1, __m256d& a2,
                                    __m256d& v0, __m256d& v1, __m256d& v2, __m256d& theta, int& bad) {
  const __m256d zero = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.0);
  const __m256d res = residual(jt, bt, h, a0, a1, a2, v0, v1, v2);
  const __m256d pos = _mm256_and_pd(_mm256_cmp_pd(zero, ln, _CMP_LT_OQ), ln);  // max_of(0, λ_n)
  const __m256d t = _mm256_mul_pd(L(mu + h), pos);
  const __m256d y = _mm256_sub_pd(old, res);
  const __m256d nt = _mm256_xor_pd(t, sign);
  const __m256d m1 = _mm256_blendv_pd(y, nt, _mm256_cmp_pd(y, nt, _CMP_LT_OQ));
  const __m256d c = _mm256_blendv_pd(m1, t, _mm256_cmp_pd(t, m1, _CMP_LT_OQ));
  const __m256d active = _mm256_cmp_pd(zero, t, _CMP_LT_OQ);
  const __m256d x = _mm256_and_pd(active, c);
  bad |= nonfinite(_mm256_blendv_pd(y, x, active));
  const __m256d d = _mm256_sub_pd(x, old);
  update(mjt, h, d, a0, a1, a2, v0, v1, v2);
  theta = _mm256_max_pd(theta, _mm256_andnot_pd(sign, d));
  return x;
}

/// Lanes h..h+3 of pair batch P (λ at lin/lout + 32·bi): sweep_pairs_scalar's operations.
DC_AVX2 inline void pair_half(const PairBatch& P, int h, const double* lin, double* lout, double* u, __m256d& theta,
                              int& bad) {
  const __m256d zero = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.0);
  __m256d a0, a1, a2, v0, v1, v2;
  load4(u, P.la + h, a0, a1, a2);
  load4(u, P.lb + h, v0, v1, v2);
  const __m256d l0 = LU(lin + h), l1 = LU(lin + 2 * W + h);
  _mm256_storeu_pd(lout + W + h, pair_tangent(P.jt0, P.mjt0, P.bt0, P.mu0, h, l0, LU(lin + W + h), a0, a1, a2, v0,
                                              v1, v2, theta, bad));
  _mm256_storeu_pd(lout + 3 * W + h, pair_tangent(P.jt1, P.mjt1, P.bt1, P.mu1, h, l1, LU(lin + 3 * W + h), a0, a1,
                                                  a2, v0, v1, v2, theta, bad));
  const __m256d res0 = residual(P.jn0, P.bn0, h, a0, a1, a2, v0, v1, v2);
  const __m256d res1 = residual(P.jn1, P.bn1, h, a0, a1, a2, v0, v1, v2);
  const __m256d c01 = L(P.c01 + h), c10 = L(P.c10 + h), inv_det = L(P.inv_det + h);
  const __m256d beta0 = _mm256_sub_pd(_mm256_sub_pd(res0, l0), _mm256_mul_pd(c01, l1));
  const __m256d beta1 = _mm256_sub_pd(_mm256_sub_pd(res1, l1), _mm256_mul_pd(c10, l0));
  const __m256d both0 = _mm256_mul_pd(_mm256_sub_pd(_mm256_mul_pd(c01, beta1), beta0), inv_det);
  const __m256d both1 = _mm256_mul_pd(_mm256_sub_pd(_mm256_mul_pd(c10, beta0), beta1), inv_det);
  const __m256d nb0 = _mm256_xor_pd(beta0, sign), nb1 = _mm256_xor_pd(beta1, sign);
  const __m256d y0 = _mm256_sub_pd(l0, res0);
  const __m256d f0 = _mm256_andnot_pd(_mm256_cmp_pd(y0, zero, _CMP_LT_OQ), y0);
  const __m256d y1 = _mm256_sub_pd(l1, _mm256_add_pd(res1, _mm256_mul_pd(c10, _mm256_sub_pd(f0, l0))));
  const __m256d f1 = _mm256_andnot_pd(_mm256_cmp_pd(y1, zero, _CMP_LT_OQ), y1);
  const __m256d blk = _mm256_cmp_pd(zero, L(P.block + h), _CMP_LT_OQ);
  const __m256d case1 = _mm256_and_pd(blk, _mm256_and_pd(ge0(both0), ge0(both1)));
  const __m256d case2 =
      _mm256_and_pd(blk, _mm256_and_pd(ge0(nb0), ge0(_mm256_add_pd(_mm256_mul_pd(c10, nb0), beta1))));
  const __m256d case3 =
      _mm256_and_pd(blk, _mm256_and_pd(ge0(nb1), ge0(_mm256_add_pd(_mm256_mul_pd(c01, nb1), beta0))));
  const __m256d case4 = _mm256_and_pd(blk, _mm256_and_pd(ge0(beta0), ge0(beta1)));
  __m256d x0 = _mm256_blendv_pd(f0, zero, _mm256_or_pd(case3, case4));
  x0 = _mm256_blendv_pd(x0, nb0, case2);
  x0 = _mm256_blendv_pd(x0, both0, case1);
  __m256d x1 = _mm256_blendv_pd(f1, zero, case4);
  x1 = _mm256_blendv_pd(x1, nb1, case3);
  x1 = _mm256_blendv_pd(x1, zero, case2);
  x1 = _mm256_blendv_pd(x1, both1, case1);
  bad |= nonfinite(x0) | nonfinite(x1);
  const __m256d d0 = _mm256_sub_pd(x0, l0), d1 = _mm256_sub_pd(x1, l1);
  _mm256_storeu_pd(lout + h, x0);
  _mm256_storeu_pd(lout + 2 * W + h, x1);
  update(P.mjn0, h, d0, a0, a1, a2, v0, v1, v2);
  update(P.mjn1, h, d1, a0, a1, a2, v0, v1, v2);
  theta = _mm256_max_pd(theta, _mm256_andnot_pd(sign, d0));
  theta = _mm256_max_pd(theta, _mm256_andnot_pd(sign, d1));
  const __m256d z = _mm256_add_pd(
      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a0, zero), _mm256_mul_pd(a1, zero)),
                    _mm256_add_pd(_mm256_mul_pd(a2, zero), _mm256_mul_pd(v0, zero))),
      _mm256_add_pd(_mm256_mul_pd(v1, zero), _mm256_mul_pd(v2, zero)));
  bad |= _mm256_movemask_pd(_mm256_cmp_pd(z, z, _CMP_UNORD_Q));
  store4(u, P.la + h, P.ka + h, a0, a1, a2);
  store4(u, P.lb + h, P.kb + h, v0, v1, v2);
}

/// max_of over the 4 lanes of θ, into acc.
DC_AVX2 inline void reduce(__m256d theta, int bad, Acc& acc) {
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, theta);
  double m = lanes[0];
  for (int k = 1; k < 4; ++k) m = max_of(m, lanes[k]);
  acc.theta = max_of(acc.theta, m);
  acc.bad = acc.bad || bad != 0;
}

}  // namespace

DC_AVX2 void sweep_pairs_avx2(const PairBatch* __restrict pairs, int b0, int b1, const double* __restrict in,
                              double* __restrict out, double* __restrict u, Acc& acc) {
  __m256d theta = _mm256_set1_pd(acc.theta);
  int bad = 0;
  for (int bi = b0; bi < b1; ++bi) {
    const PairBatch& P = pairs[bi];
    const double* lin = in + static_cast<long>(bi) * 4 * W;
    double* lout = out + static_cast<long>(bi) * 4 * W;
    pair_half(P, 0, lin, lout, u, theta, bad);
    if (P.count > 4) {
      pair_half(P, 4, lin, lout, u, theta, bad);
    } else {
      for (int r = 0; r < 4; ++r) _mm256_storeu_pd(lout + r * W + 4, _mm256_setzero_pd());
    }
  }
  reduce(theta, bad, acc);
}

namespace {

/// One batch (λ at lin/lout; a Batch, or a CompactBatch with compact = true) as two halves of 4 lanes.
template <bool compact, class BatchT>
DC_AVX2 inline void single_batch(const BatchT& B, const double* lin, double* lout, double* u, __m256d& theta,
                                 int& bad) {
  using Rows = std::conditional_t<compact, CompactRows, FullRows>;
  // The two halves touch distinct bodies (one colour), so their order does not matter;
  // a half without contacts (the tail of a colour) is all padding and is skipped.
  half(B, Rows(B, 0), 0, lin, lout, u, theta, bad);
  if (B.count > 4) {
    half(B, Rows(B, 4), 4, lin, lout, u, theta, bad);
  } else {
    _mm256_storeu_pd(lout + 4, _mm256_setzero_pd());
    _mm256_storeu_pd(lout + W + 4, _mm256_setzero_pd());
  }
}

}  // namespace

DC_AVX2 void sweep_avx2(const Batch* __restrict batches, int b0, int b1, const double* __restrict in,
                        double* __restrict out, double* __restrict u, Acc& acc) {
  __m256d theta = _mm256_set1_pd(acc.theta);
  int bad = 0;
  for (int bi = b0; bi < b1; ++bi)
    single_batch<false>(batches[bi], in + static_cast<long>(bi) * 2 * W, out + static_cast<long>(bi) * 2 * W, u, theta,
                 bad);
  reduce(theta, bad, acc);
}

DC_AVX2 void sweep_compact_avx2(const CompactBatch* __restrict batches, int b0, int b1, const double* __restrict in,
                                double* __restrict out, double* __restrict u, Acc& acc) {
  __m256d theta = _mm256_set1_pd(acc.theta);
  int bad = 0;
  for (int bi = b0; bi < b1; ++bi)
    single_batch<true>(batches[bi], in + static_cast<long>(bi) * 2 * W, out + static_cast<long>(bi) * 2 * W, u, theta,
                       bad);
  reduce(theta, bad, acc);
}

bool cpu_has_avx2() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
bool cpu_is_amd() { return __builtin_cpu_is("amd"); }
int cpu_family() {
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (__get_cpuid(1, &a, &b, &c, &d) == 0) return 0;
  return static_cast<int>(((a >> 8) & 0xFU) + ((a >> 20) & 0xFFU));
}

}  // namespace dc::colored

#else

namespace dc::colored {
void sweep_avx2(const Batch*, int, int, const double*, double*, double*, Acc&) {}
void sweep_pairs_avx2(const PairBatch*, int, int, const double*, double*, double*, Acc&) {}
void sweep_compact_avx2(const CompactBatch*, int, int, const double*, double*, double*, Acc&) {}
bool cpu_has_avx2() { return false; }
bool cpu_is_amd() { return false; }
int cpu_family() { return 0; }
}  // namespace dc::colored

#endif
