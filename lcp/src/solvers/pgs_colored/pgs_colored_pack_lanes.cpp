// Batch packing across lanes for pgs-colored (pgs_colored_pack_lanes.hpp).
#include "solvers/pgs_colored/pgs_colored_pack_lanes.hpp"

#include <algorithm>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace dc::colored {
namespace {

/// Where the lanes' rows of one kind (normal or tangent) start in J's storage and on which
/// columns: q = first stored entry (−1: no row, a padding lane or no friction), n = entries (3 or
/// 6), a / bb = the first column of the first / second body (bb = a when there is none).
struct LaneRows {
  int q[W], n[W], a[W], bb[W];
};

/// True when row i of J is stored as n = 3 or 6 entries on columns a, a+1, a+2 (, bb, bb+1,
/// bb+2) in order (bb < 0: one body): pack_row's usual-storage branch. Sets q to its first entry.
inline bool usual_row(const LcpProblem& p, int i, int a, int bb, int& q, int& n) {
  const int* outer = p.J.outerIndexPtr();
  const int* nnz = p.J.innerNonZeroPtr();
  q = outer[i];
  n = (nnz != nullptr ? nnz[i] : outer[i + 1] - q);
  const int* col = p.J.innerIndexPtr() + q;
  return n == (bb < 0 ? 3 : 6) && col[0] == a && col[1] == a + 1 && col[2] == a + 2 &&
         (bb < 0 || (col[3] == bb && col[4] == bb + 1 && col[5] == bb + 2));
}

#if defined(__AVX2__)
/// pack_kind on 4 lanes (lane0 = 0 or 4) with AVX2 gathers: the same multiplications and
/// additions per lane; a lane without the entry gathers 0 (masked), whose products add +0 to
/// A_ii, which is never −0 (a sum from +0 of the products r·r·M⁻¹·Δt), so it is unchanged.
void pack_kind_avx2(const LcpProblem& p, const LaneRows& L, const int* row, double (*j)[W], double (*mj)[W],
                    double* b, double* diag, int lane0) {
  const double* value = p.J.valuePtr();
  const double* im = p.inv_mass.data();
  const __m256d dt = _mm256_set1_pd(p.dt), zero = _mm256_setzero_pd();
  const __m128i q = _mm_loadu_si128(reinterpret_cast<const __m128i*>(L.q + lane0));
  const __m128i n = _mm_loadu_si128(reinterpret_cast<const __m128i*>(L.n + lane0));
  const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(L.a + lane0));
  const __m128i bb = _mm_loadu_si128(reinterpret_cast<const __m128i*>(L.bb + lane0));
  const __m128i has = _mm_cmpgt_epi32(q, _mm_set1_epi32(-1));
  __m256d d = zero;
  for (int s = 0; s < 6; ++s) {
    const __m128i on32 = _mm_and_si128(has, _mm_cmpgt_epi32(n, _mm_set1_epi32(s)));
    const __m256d on = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(on32));
    const __m128i qi = _mm_add_epi32(q, _mm_set1_epi32(s));
    const __m128i ci = s < 3 ? _mm_add_epi32(a, _mm_set1_epi32(s)) : _mm_add_epi32(bb, _mm_set1_epi32(s - 3));
    const __m256d r = _mm256_add_pd(zero, _mm256_mask_i32gather_pd(zero, value, qi, on, 8));
    const __m256d inv = _mm256_mask_i32gather_pd(zero, im, ci, on, 8);
    const __m256d m = _mm256_mul_pd(_mm256_mul_pd(r, inv), dt);
    d = _mm256_add_pd(d, _mm256_mul_pd(r, m));
    _mm256_storeu_pd(j[s] + lane0, r);
    _mm256_storeu_pd(mj[s] + lane0, m);
  }
  const __m256d hasd = _mm256_castsi256_pd(_mm256_cvtepi32_epi64(has));
  const __m128i rows = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + lane0));
  _mm256_storeu_pd(b + lane0, _mm256_mask_i32gather_pd(zero, p.b.data(), rows, hasd, 8));
  _mm256_storeu_pd(diag + lane0, _mm256_blendv_pd(_mm256_set1_pd(1.0), d, hasd));
}
#endif

/// The coefficients of one row kind on all lanes: j[s][lane] = r, mj[s][lane] = r·M⁻¹·Δt and
/// diag[lane] = Σ_s r·m (lanes without a row: zeros and A_ii = 1), b[lane] = b_i.
void pack_kind(const LcpProblem& p, const LaneRows& L, const int* row, double (*j)[W], double (*mj)[W], double* b,
               double* diag) {
#if defined(__AVX2__)
  pack_kind_avx2(p, L, row, j, mj, b, diag, 0);
  pack_kind_avx2(p, L, row, j, mj, b, diag, 4);
#else
  const double* value = p.J.valuePtr();
  const double* im = p.inv_mass.data();
  const double dt = p.dt;
  double d[W];
  for (int lane = 0; lane < W; ++lane) d[lane] = 0.0;
  for (int s = 0; s < 6; ++s) {
#pragma omp simd
    for (int lane = 0; lane < W; ++lane) {
      const bool on = L.q[lane] >= 0 && s < L.n[lane];
      const int qi = on ? L.q[lane] + s : 0;
      const int ci = on ? (s < 3 ? L.a[lane] + s : L.bb[lane] + s - 3) : 0;
      const double r = on ? 0.0 + value[qi] : 0.0;
      const double m = on ? r * im[ci] * dt : 0.0;
      d[lane] = on ? d[lane] + r * m : d[lane];
      j[s][lane] = r;
      mj[s][lane] = m;
    }
  }
  const double* bv = p.b.data();
  for (int lane = 0; lane < W; ++lane) {
    const bool on = L.q[lane] >= 0;
    b[lane] = on ? bv[row[lane]] : 0.0;
    diag[lane] = on ? d[lane] : 1.0;
  }
#endif
}

}  // namespace

bool pack_lanes(const LcpProblem& p, const std::vector<std::uint8_t>& dynamic, int zero, const int* contacts,
                int lanes, Batch& B, int* row_n, int* row_t, double* diag_n, double* diag_t) {
  LaneRows N{}, T{};
  for (int lane = 0; lane < W; ++lane) {
    if (lane >= lanes) {
      N.q[lane] = T.q[lane] = -1;
      N.n[lane] = T.n[lane] = N.a[lane] = T.a[lane] = N.bb[lane] = T.bb[lane] = 0;
      row_n[lane] = row_t[lane] = -1;
      B.mu[lane] = 0.0;
      B.la[lane] = B.lb[lane] = zero;
      B.ka[lane] = B.kb[lane] = 0;
      continue;
    }
    const ContactConstraint& k = p.constraints[contacts[lane]];
    const int first = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
    const int second = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
    const int a = 3 * first, bb = second < 0 ? -1 : 3 * second;
    if (!usual_row(p, k.normal_row, a, bb, N.q[lane], N.n[lane])) return false;
    N.a[lane] = T.a[lane] = a;
    N.bb[lane] = T.bb[lane] = bb < 0 ? a : bb;
    if (k.has_friction()) {
      if (!usual_row(p, k.tangent_row, a, bb, T.q[lane], T.n[lane])) return false;
      B.mu[lane] = k.mu;
    } else {
      T.q[lane] = -1;
      T.n[lane] = 0;
      B.mu[lane] = 0.0;
    }
    const bool da = dynamic[static_cast<size_t>(first)] != 0;
    const bool db = second >= 0 && dynamic[static_cast<size_t>(second)] != 0;
    B.la[lane] = da ? kStride * first : zero;
    B.lb[lane] = db ? kStride * second : zero;
    B.ka[lane] = da ? 1 : 0;
    B.kb[lane] = db ? 1 : 0;
    row_n[lane] = k.normal_row;
    row_t[lane] = k.tangent_row;
  }
  pack_kind(p, N, row_n, B.jn, B.mjn, B.bn, diag_n);
  pack_kind(p, T, row_t, B.jt, B.mjt, B.bt, diag_t);
  return true;
}

}  // namespace dc::colored
