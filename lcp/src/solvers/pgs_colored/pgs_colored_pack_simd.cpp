// pgs-colored's row packing, 4 lanes per AVX2 register, and the compact pack's 8 lanes per AVX-512
// register (pgs_colored_pack_simd.hpp). Compiled for AVX2 / AVX-512 by function attribute in
// every x86-64 build and chosen at run time, as the sweep kernels.
// No FMA: pack_row's products and sums round one at a time (the build has no FP contraction).
#include "solvers/pgs_colored/pgs_colored_pack_simd.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include <limits>

#define DC_PACK_AVX2 __attribute__((target("avx2")))

namespace dc::colored {
namespace {

/// Where row i's entries of J start, and their count.
inline int row_extent(const SparseRowMatrix& J, int i, int& q0) {
  q0 = J.outerIndexPtr()[i];
  return J.isCompressed() ? J.outerIndexPtr()[i + 1] - q0 : J.innerNonZeroPtr()[i];
}

/// pack_row's usual storage: row i has the columns a, a+1, a+2 (, bb, bb+1, bb+2), once each.
inline bool usual(const SparseRowMatrix& J, int i, int a, int bb, int& q0) {
  const int n = row_extent(J, i, q0);
  const int* col = J.innerIndexPtr() + q0;
  return n == (bb < 0 ? 3 : 6) && col[0] == a && col[1] == a + 1 && col[2] == a + 2 &&
         (bb < 0 || (col[3] == bb && col[4] == bb + 1 && col[5] == bb + 2));
}

/// Rows r0..r3 (4 doubles each) as columns: c[s] = (r0[s], r1[s], r2[s], r3[s]).
DC_PACK_AVX2 inline void transpose4(__m256d r0, __m256d r1, __m256d r2, __m256d r3, __m256d* c) {
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1);  // r0_0 r1_0 | r0_2 r1_2
  const __m256d t1 = _mm256_unpackhi_pd(r0, r1);  // r0_1 r1_1 | r0_3 r1_3
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3);
  const __m256d t3 = _mm256_unpackhi_pd(r2, r3);
  c[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
  c[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
  c[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
  c[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}

/// Lanes h..h+3 of a row, unscaled (entries of J at value + q0[k], M⁻¹ at im + a[k], im + bb[k]):
/// r_s = 0 + J_is in v, m_s = M⁻¹J_isΔt in m, A_ii = Σ r_s·m_s in slot order in sum.
DC_PACK_AVX2 inline void rows4(const double* value, const double* im, double dt, const int* q0, const int* a,
                               const int* bb, int h, __m256d* v, __m256d* m, __m256d& sum) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256i three = _mm256_setr_epi64x(-1, -1, -1, 0);  // the first 3 of 4 doubles
  __m256d lo[4], ia[4], ib[4];
  __m128d hi[4];
  int two = 0;  // lanes with a second body
  for (int k = 0; k < 4; ++k) {
    const int l = h + k;
    const double* vl = value + q0[l];
    const bool second = bb[l] >= 0;
    two |= second ? 1 << k : 0;
    // (masked loads: nothing beyond the row's entries or the body's 3 M⁻¹ entries is read)
    lo[k] = second ? _mm256_loadu_pd(vl) : _mm256_maskload_pd(vl, three);
    hi[k] = second ? _mm_loadu_pd(vl + 4) : _mm_setzero_pd();
    ia[k] = _mm256_maskload_pd(im + a[l], three);
    ib[k] = second ? _mm256_maskload_pd(im + bb[l], three) : zero;
  }
  __m256d ima[4], imb[4];
  transpose4(lo[0], lo[1], lo[2], lo[3], v);
  const __m256d h02 = _mm256_set_m128d(hi[2], hi[0]), h13 = _mm256_set_m128d(hi[3], hi[1]);
  v[4] = _mm256_unpacklo_pd(h02, h13);
  v[5] = _mm256_unpackhi_pd(h02, h13);
  transpose4(ia[0], ia[1], ia[2], ia[3], ima);
  transpose4(ib[0], ib[1], ib[2], ib[3], imb);
  // Lanes with one body: slots 3–5 are r = +0 (the loads above) and m = +0, as pack_row writes
  // them; they add +0 to A_ii, which leaves it unchanged (it is never −0: it starts at 0 + ·).
  const __m256d has_b = _mm256_castsi256_pd(_mm256_setr_epi64x((two & 1) ? -1 : 0, (two & 2) ? -1 : 0,
                                                                (two & 4) ? -1 : 0, (two & 8) ? -1 : 0));
  const __m256d dtv = _mm256_set1_pd(dt);
  sum = zero;
  for (int s = 0; s < 6; ++s) {
    v[s] = _mm256_add_pd(zero, v[s]);  // r = 0 + J_is (−0 → +0)
    m[s] = _mm256_mul_pd(_mm256_mul_pd(v[s], s < 3 ? ima[s] : imb[s - 3]), dtv);
    if (s >= 3) m[s] = _mm256_and_pd(m[s], has_b);
    sum = _mm256_add_pd(sum, _mm256_mul_pd(v[s], m[s]));
  }
}

/// The 4-bit mask of the lanes whose A_ii (sum) is not finite and > 0 or 1/A_ii (inv) not finite
/// (scale_rows's test).
DC_PACK_AVX2 inline unsigned singular4(__m256d sum, __m256d inv) {
  const __m256d inf = _mm256_set1_pd(std::numeric_limits<double>::infinity());
  const __m256d abs_inv = _mm256_andnot_pd(_mm256_set1_pd(-0.0), inv);
  const __m256d positive = _mm256_and_pd(_mm256_cmp_pd(sum, _mm256_setzero_pd(), _CMP_GT_OQ),
                                         _mm256_cmp_pd(sum, inf, _CMP_LT_OQ));
  const __m256d good = _mm256_and_pd(positive, _mm256_cmp_pd(abs_inv, inf, _CMP_LT_OQ));
  return static_cast<unsigned>(~_mm256_movemask_pd(good)) & 0xFu;
}

/// Lanes h..h+3 packed (rows4, then j = r·(1/A_ii), b = b_i·(1/A_ii)); returns the 4-bit mask
/// of singular lanes.
DC_PACK_AVX2 unsigned pack4(const double* value, const double* im, double dt, const double* bi, const int* q0,
                            const int* a, const int* bb, double (*j)[W], double (*mj)[W], double* b, double* diag,
                            int h) {
  __m256d v[6], m[6], sum;
  rows4(value, im, dt, q0, a, bb, h, v, m, sum);
  const __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), sum);
  for (int s = 0; s < 6; ++s) {
    _mm256_store_pd(j[s] + h, _mm256_mul_pd(v[s], inv));
    _mm256_store_pd(mj[s] + h, m[s]);
  }
  const __m256d bv = _mm256_setr_pd(bi[0], bi[1], bi[2], bi[3]);
  _mm256_store_pd(b + h, _mm256_mul_pd(bv, inv));
  _mm256_storeu_pd(diag + h, sum);
  return singular4(sum, inv);
}

/// The 4-bit masks of the lanes where x is not +0 bit for bit, and where x and y are equal bit
/// for bit.
DC_PACK_AVX2 inline unsigned nonzero4(__m256d x) {
  const __m256i z = _mm256_cmpeq_epi64(_mm256_castpd_si256(x), _mm256_setzero_si256());
  return static_cast<unsigned>(~_mm256_movemask_pd(_mm256_castsi256_pd(z))) & 0xFu;
}
DC_PACK_AVX2 inline unsigned same4(__m256d x, __m256d y) {
  const __m256i e = _mm256_cmpeq_epi64(_mm256_castpd_si256(x), _mm256_castpd_si256(y));
  return static_cast<unsigned>(_mm256_movemask_pd(_mm256_castsi256_pd(e)));
}

/// Lanes h..h+3 of one row of a compact batch: pack4's coefficients, j and b times ω (when ≠ 1,
/// as over_relax), only the stored ones written (j: slots 0, 1, 2, 5; mj: all 6 for the normal
/// row, slots 2, 5 for the tangent row, whose normal mj `mjn` is read). The derived ones are
/// computed in registers and compared bit for bit with compress()'s derivation: `nz_j` / `same_j`
/// the lanes whose j slots 3, 4 are not both +0 / equal 0 − j_0, 0 − j_1; for the tangent row
/// `nz_m` / `same_m` the same for mj slots 0, 1, 3, 4 and 0 − mjn_1, mjn_0, 0 − mjn_4, mjn_3.
struct Compare4 {
  unsigned nz_j = 0, same_j = 0, nz_m = 0, same_m = 0;
};
DC_PACK_AVX2 unsigned compact4(const double* value, const double* im, double dt, const double* bi, const int* q0,
                               const int* a, const int* bb, double omega, bool tangent, double (*j)[W],
                               double (*mj)[W], double (*mjn)[W], double* b, double* diag, int h, Compare4& c) {
  __m256d v[6], m[6], sum;
  rows4(value, im, dt, q0, a, bb, h, v, m, sum);
  const __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), sum);
  const __m256d om = _mm256_set1_pd(omega);
  const bool relax = omega != 1.0;
  __m256d js[6];
  for (int s = 0; s < 6; ++s) {
    js[s] = _mm256_mul_pd(v[s], inv);
    if (relax) js[s] = _mm256_mul_pd(js[s], om);
  }
  constexpr int kept[4] = {0, 1, 2, 5};
  for (int q = 0; q < 4; ++q) _mm256_store_pd(j[q] + h, js[kept[q]]);
  const __m256d zero = _mm256_setzero_pd();
  c.nz_j = nonzero4(_mm256_or_pd(js[3], js[4]));
  c.same_j = same4(js[3], _mm256_sub_pd(zero, js[0])) & same4(js[4], _mm256_sub_pd(zero, js[1]));
  if (!tangent) {
    for (int s = 0; s < 6; ++s) _mm256_store_pd(mj[s] + h, m[s]);
  } else {
    _mm256_store_pd(mj[0] + h, m[2]);
    _mm256_store_pd(mj[1] + h, m[5]);
    c.nz_m = nonzero4(_mm256_or_pd(_mm256_or_pd(m[0], m[1]), _mm256_or_pd(m[3], m[4])));
    const __m256d n0 = _mm256_load_pd(mjn[0] + h), n1 = _mm256_load_pd(mjn[1] + h);
    const __m256d n3 = _mm256_load_pd(mjn[3] + h), n4 = _mm256_load_pd(mjn[4] + h);
    c.same_m = same4(m[0], _mm256_sub_pd(zero, n1)) & same4(m[1], n0) & same4(m[3], _mm256_sub_pd(zero, n4)) &
               same4(m[4], n3);
  }
  __m256d bs = _mm256_mul_pd(_mm256_setr_pd(bi[0], bi[1], bi[2], bi[3]), inv);
  if (relax) bs = _mm256_mul_pd(bs, om);
  _mm256_store_pd(b + h, bs);
  _mm256_storeu_pd(diag + h, sum);
  return singular4(sum, inv);
}

/// pack_compact_simd's rows on 4 lanes per AVX2 register: lane l's normal row entries at
/// value + qn[l], its tangent row's at value + qt[l], b_i in bn[l], bt[l], M⁻¹ at im + a[l],
/// im + bb[l]; compact4 on lanes 0–3, then 4–7.
DC_PACK_AVX2 void compact_rows4x2(const double* value, const double* im, double dt, const int* qn, const int* qt,
                                  const double* bn, const double* bt, const int* a, const int* bb, double omega,
                                  CompactBatch& C, double* diag_n, double* diag_t, unsigned& singular, unsigned& two,
                                  unsigned& fric, bool& exact) {
  unsigned nz_two = 0, nz_fric = 0, differ = 0;
  singular = 0;
  for (int h = 0; h < W; h += 4) {
    Compare4 n, t;
    // (the normal row first: the tangent's comparison reads its M⁻¹JᵀΔt)
    const unsigned sn = compact4(value, im, dt, bn + h, qn, a, bb, omega, false, C.jn, C.mjn, C.mjn, C.bn, diag_n, h, n);
    const unsigned st = compact4(value, im, dt, bt + h, qt, a, bb, omega, true, C.jt, C.mjt, C.mjn, C.bt, diag_t, h, t);
    singular |= (sn | st) << h;
    const unsigned tw = n.nz_j | t.nz_j;  // compress()'s bit of `two`: a derived j slot not +0
    nz_two |= tw << h;
    nz_fric |= t.nz_m << h;
    // Where the bit is set, every derived slot must equal its derivation; where it is clear they
    // are all +0, as the derivation's +0.
    differ |= ((tw & ~(n.same_j & t.same_j)) | (t.nz_m & ~t.same_m)) << h;
  }
  two = nz_two;
  fric = nz_fric;
  exact = differ == 0;
}

// ---- AVX-512: all W = 8 lanes of a row in one register ------------------------------------
#define DC_PACK_AVX512 __attribute__((target("avx512f,avx512dq,avx512vl")))

/// nonzero4 and same4 on 8 lanes (not lambdas: a lambda does not take its function's target).
DC_PACK_AVX512 inline unsigned nonzero8(__m512d x) {
  return static_cast<unsigned>(_mm512_test_epi64_mask(_mm512_castpd_si512(x), _mm512_castpd_si512(x)));
}
DC_PACK_AVX512 inline unsigned same8(__m512d x, __m512d y) {
  return static_cast<unsigned>(_mm512_cmpeq_epi64_mask(_mm512_castpd_si512(x), _mm512_castpd_si512(y)));
}

/// compact4's row on all 8 lanes, the sources gathered (no transposes): lane l's J entries at
/// value + q0[l] (slots 3–5 only on the lanes of `two_b`, the lanes with a second body; +0
/// elsewhere, as rows4 loads them), its M⁻¹ at im + a[l] and im + bb[l]. The same operations on
/// each lane in the same order as rows4 and compact4, so the same bits. The normal row (mjn
/// null) stores all 6 mj slots; the tangent row stores slots 2, 5 and compares 0, 1, 3, 4 with
/// the normal's (mjn) as compact4. The masks are compact4's, 8 bits wide.
DC_PACK_AVX512 unsigned compact8(const double* value, __m512d ima[3], __m512d imb[3], __mmask8 two_b, double dt,
                                 const double* bi, const int* q0, double omega, double (*j)[W], double (*mj)[W],
                                 const double (*mjn)[W], double* b, double* diag, Compare4& c) {
  const __m256i q = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(q0));
  const __m512d zero = _mm512_setzero_pd(), dtv = _mm512_set1_pd(dt);
  __m512d v[6], m[6];
  __m512d sum = zero;
  for (int s = 0; s < 6; ++s) {
    const __m256i at = _mm256_add_epi32(q, _mm256_set1_epi32(s));
    const __m512d e = _mm512_mask_i32gather_pd(zero, s < 3 ? __mmask8(0xFF) : two_b, at, value, 8);
    v[s] = _mm512_add_pd(zero, e);  // r = 0 + J_is (−0 → +0)
    m[s] = _mm512_mul_pd(_mm512_mul_pd(v[s], s < 3 ? ima[s] : imb[s - 3]), dtv);
    if (s >= 3) m[s] = _mm512_maskz_mov_pd(two_b, m[s]);
    sum = _mm512_add_pd(sum, _mm512_mul_pd(v[s], m[s]));
  }
  const __m512d inv = _mm512_div_pd(_mm512_set1_pd(1.0), sum);
  const __m512d om = _mm512_set1_pd(omega);
  const bool relax = omega != 1.0;
  __m512d js[6];
  for (int s = 0; s < 6; ++s) {
    js[s] = _mm512_mul_pd(v[s], inv);
    if (relax) js[s] = _mm512_mul_pd(js[s], om);
  }
  constexpr int kept[4] = {0, 1, 2, 5};
  for (int k = 0; k < 4; ++k) _mm512_store_pd(j[k], js[kept[k]]);
  c.nz_j = nonzero8(_mm512_or_pd(js[3], js[4]));
  c.same_j = same8(js[3], _mm512_sub_pd(zero, js[0])) & same8(js[4], _mm512_sub_pd(zero, js[1]));
  if (mjn == nullptr) {
    for (int s = 0; s < 6; ++s) _mm512_store_pd(mj[s], m[s]);
  } else {
    _mm512_store_pd(mj[0], m[2]);
    _mm512_store_pd(mj[1], m[5]);
    c.nz_m = nonzero8(_mm512_or_pd(_mm512_or_pd(m[0], m[1]), _mm512_or_pd(m[3], m[4])));
    const __m512d n0 = _mm512_load_pd(mjn[0]), n1 = _mm512_load_pd(mjn[1]);
    const __m512d n3 = _mm512_load_pd(mjn[3]), n4 = _mm512_load_pd(mjn[4]);
    c.same_m = same8(m[0], _mm512_sub_pd(zero, n1)) & same8(m[1], n0) & same8(m[3], _mm512_sub_pd(zero, n4)) &
               same8(m[4], n3);
  }
  __m512d bs = _mm512_mul_pd(_mm512_loadu_pd(bi), inv);
  if (relax) bs = _mm512_mul_pd(bs, om);
  _mm512_store_pd(b, bs);
  _mm512_storeu_pd(diag, sum);
  // singular4's test: A_ii finite and > 0, 1/A_ii finite
  const __m512d inf = _mm512_set1_pd(std::numeric_limits<double>::infinity());
  const __mmask8 good = _mm512_cmp_pd_mask(sum, zero, _CMP_GT_OQ) & _mm512_cmp_pd_mask(sum, inf, _CMP_LT_OQ) &
                        _mm512_cmp_pd_mask(_mm512_abs_pd(inv), inf, _CMP_LT_OQ);
  return static_cast<unsigned>(~good) & 0xFFu;
}

/// pack_compact_simd's rows on all 8 lanes (compact8 for the normal, then the tangent row; the
/// bodies' M⁻¹ gathered once for both). Same outputs as the AVX2 loop.
DC_PACK_AVX512 void compact_rows8(const double* value, const double* im, double dt, const int* qn, const int* qt,
                                  const double* bn, const double* bt, const int* a, const int* bb, double omega,
                                  CompactBatch& C, double* diag_n, double* diag_t, unsigned& singular, unsigned& two,
                                  unsigned& fric, bool& exact) {
  const __m256i ia = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a));
  const __m256i ib = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(bb));
  const __mmask8 two_b = _mm256_cmpge_epi32_mask(ib, _mm256_setzero_si256());
  const __m512d zero = _mm512_setzero_pd();
  __m512d ima[3], imb[3];
  for (int s = 0; s < 3; ++s) {
    ima[s] = _mm512_mask_i32gather_pd(zero, 0xFF, _mm256_add_epi32(ia, _mm256_set1_epi32(s)), im, 8);
    imb[s] = _mm512_mask_i32gather_pd(zero, two_b, _mm256_add_epi32(ib, _mm256_set1_epi32(s)), im, 8);
  }
  Compare4 n, t;
  // (the normal row first: the tangent's comparison reads its M⁻¹JᵀΔt)
  const unsigned sn = compact8(value, ima, imb, two_b, dt, bn, qn, omega, C.jn, C.mjn, nullptr, C.bn, diag_n, n);
  const unsigned st = compact8(value, ima, imb, two_b, dt, bt, qt, omega, C.jt, C.mjt, C.mjn, C.bt, diag_t, t);
  singular = sn | st;
  const unsigned tw = n.nz_j | t.nz_j;
  two = tw;
  fric = t.nz_m;
  exact = ((tw & ~(n.same_j & t.same_j)) | (t.nz_m & ~t.same_m)) == 0;
}

/// usual() with the columns compared in one masked vector compare: row i's n entries (3 or 6)
/// at q0 are a, a+1, a+2 (, bb, bb+1, bb+2). Nothing beyond the row's entries is read.
DC_PACK_AVX512 inline bool usual_wide(const SparseRowMatrix& J, int i, int a, int bb, int& q0) {
  const int n = row_extent(J, i, q0);
  const __mmask8 want = bb < 0 ? 0x07 : 0x3F;
  if (n != (bb < 0 ? 3 : 6)) return false;
  const __m256i col = _mm256_maskz_loadu_epi32(want, J.innerIndexPtr() + q0);
  const __m256i expect = _mm256_add_epi32(_mm256_setr_epi32(a, a, a, bb, bb, bb, 0, 0),
                                          _mm256_setr_epi32(0, 1, 2, 0, 1, 2, 0, 0));
  return _mm256_mask_cmpeq_epi32_mask(want, col, expect) == want;
}

/// pack_compact_simd on AVX-512: the storage checks (usual_wide), b, and compact_rows8.
DC_PACK_AVX512 bool pack_compact_wide(const LcpProblem& p, const int* rn, const int* rt, const int* a, const int* bb,
                                      double omega, CompactBatch& C, double* diag_n, double* diag_t,
                                      unsigned& singular, unsigned& two, unsigned& fric, bool& exact) {
  alignas(32) int qn[W], qt[W];
  alignas(64) double bn[W], bt[W];
  for (int l = 0; l < W; ++l) {
    if (!usual_wide(p.J, rn[l], a[l], bb[l], qn[l]) || !usual_wide(p.J, rt[l], a[l], bb[l], qt[l])) return false;
    bn[l] = p.b[rn[l]];
    bt[l] = p.b[rt[l]];
  }
  compact_rows8(p.J.valuePtr(), p.inv_mass.data(), p.dt, qn, qt, bn, bt, a, bb, omega, C, diag_n, diag_t, singular,
                two, fric, exact);
  return true;
}

bool avx512_pack_available() {
  static const bool ok = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
                         __builtin_cpu_supports("avx512vl");
  return ok;
}

}  // namespace

DC_PACK_AVX2 bool pack_rows_simd(const LcpProblem& p, const int* rows, const int* a, const int* bb, double (*j)[W],
                                 double (*mj)[W], double* b, double* diag, unsigned& singular) {
  static_assert(W == 8, "two groups of 4 lanes");
  if (!simd_pack_available()) return false;
  int q0[W];
  double bi[W];
  for (int l = 0; l < W; ++l) {
    if (!usual(p.J, rows[l], a[l], bb[l], q0[l])) return false;
    bi[l] = p.b[rows[l]];
  }
  const double* value = p.J.valuePtr();
  const double* im = p.inv_mass.data();
  singular = pack4(value, im, p.dt, bi, q0, a, bb, j, mj, b, diag, 0) |
             pack4(value, im, p.dt, bi + 4, q0, a, bb, j, mj, b, diag, 4) << 4;
  return true;
}

DC_PACK_AVX2 bool pack_rows_staged(const double* base, const int* off, const double* bi, const int* a, const int* bb,
                                   const double* im, double dt, double (*j)[W], double (*mj)[W], double* b,
                                   double* diag, unsigned& singular) {
  if (!simd_pack_available()) return false;
  singular = pack4(base, im, dt, bi, off, a, bb, j, mj, b, diag, 0) |
             pack4(base, im, dt, bi + 4, off, a, bb, j, mj, b, diag, 4) << 4;
  return true;
}

DC_PACK_AVX2 bool pack_compact_simd(const LcpProblem& p, const int* rn, const int* rt, const int* a, const int* bb,
                                    double omega, CompactBatch& C, double* diag_n, double* diag_t, unsigned& singular,
                                    unsigned& two, unsigned& fric, bool& exact, bool wide) {
  if (!simd_pack_available()) return false;
  if (wide && avx512_pack_available())
    return pack_compact_wide(p, rn, rt, a, bb, omega, C, diag_n, diag_t, singular, two, fric, exact);
  int qn[W], qt[W];
  double bn[W], bt[W];
  for (int l = 0; l < W; ++l) {
    if (!usual(p.J, rn[l], a[l], bb[l], qn[l]) || !usual(p.J, rt[l], a[l], bb[l], qt[l])) return false;
    bn[l] = p.b[rn[l]];
    bt[l] = p.b[rt[l]];
  }
  compact_rows4x2(p.J.valuePtr(), p.inv_mass.data(), p.dt, qn, qt, bn, bt, a, bb, omega, C, diag_n, diag_t, singular,
                  two, fric, exact);
  return true;
}

DC_PACK_AVX2 bool pack_compact_staged(const double* base, const int* on, const int* ot, const double* bn,
                                      const double* bt, const int* a, const int* bb, const double* im, double dt,
                                      double omega, CompactBatch& C, double* diag_n, double* diag_t,
                                      unsigned& singular, unsigned& two, unsigned& fric, bool& exact, bool wide) {
  if (!simd_pack_available()) return false;
  if (wide && avx512_pack_available())
    compact_rows8(base, im, dt, on, ot, bn, bt, a, bb, omega, C, diag_n, diag_t, singular, two, fric, exact);
  else
    compact_rows4x2(base, im, dt, on, ot, bn, bt, a, bb, omega, C, diag_n, diag_t, singular, two, fric, exact);
  return true;
}

bool simd_pack_available() {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2;
}

}  // namespace dc::colored

#else

namespace dc::colored {
bool pack_rows_simd(const LcpProblem&, const int*, const int*, const int*, double (*)[W], double (*)[W], double*,
                    double*, unsigned&) {
  return false;
}
bool pack_rows_staged(const double*, const int*, const double*, const int*, const int*, const double*, double,
                      double (*)[W], double (*)[W], double*, double*, unsigned&) {
  return false;
}
bool pack_compact_simd(const LcpProblem&, const int*, const int*, const int*, const int*, double, CompactBatch&,
                       double*, double*, unsigned&, unsigned&, unsigned&, bool&, bool) {
  return false;
}
bool pack_compact_staged(const double*, const int*, const int*, const double*, const double*, const int*, const int*,
                         const double*, double, double, CompactBatch&, double*, double*, unsigned&, unsigned&,
                         unsigned&, bool&, bool) {
  return false;
}
bool simd_pack_available() { return false; }
}  // namespace dc::colored

#endif
