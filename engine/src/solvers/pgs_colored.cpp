// "pgs-colored": colour-ordered matrix-free PGS, 8 contacts per AVX-512 lane group
// (dc/engine/pgs_colored.hpp). The design follows Box2D v3's graph-coloured solver (colours
// with per-body bit sets, constraints stored wide in structure-of-arrays form, an overflow set
// solved serially) with double precision and this engine's row form (J_i / A_ii pre-scaled
// as in "pgs", the same FMAs and tree sums).
//
// Data layout. A Batch holds 8 contacts of one colour in SoA form (one zmm register per
// coefficient), 27 × 8 doubles of coefficients and 4 × 8 body offsets, 1.9 kB; the batches
// are stored colour after colour, so a sweep streams them in order. λ is kept in a permuted
// vector during the sweeps (16 entries per batch: 8 λ_n, then 8 λ_t), mapped back to the
// row order at checkpoints and at the end. Δu (M⁻¹ Jᵀ λ Δt) is stored 4 doubles per body
// (Δv_x, Δv_y, Δω, 0: 32 bytes, 64-byte aligned array), followed by a zero body that absent
// bodies (walls, bodies with M⁻¹ = 0, padding lanes) are read from and never written to.
//
// Gather/scatter (where this design wins or loses). Like Box2D v3 (float body state padded
// to 32 bytes, 8 loads + a transpose), a lane group loads its 8 bodies with 8 aligned 256-bit
// loads and transposes them into 3 registers (v_x, v_y, ω: 4 inserts, 4 unpacks, 3
// two-source permutes), and writes them back with the inverse transpose and 8 masked 256-bit
// stores (lanes of absent bodies masked off: nothing is written to a shared dummy, so no
// false sharing between threads). The first version used hardware gathers/scatters
// (vgatherdpd/vscatterdpd, 6 + 6 per batch): on Zen 4 the scatters alone made it only 1.35×
// faster than the scalar lane loop (benchmarks/micro/micro_pgs.cpp). Bodies of one colour are distinct,
// so the stores of a batch never collide.
//
// Lane arithmetic = scalar arithmetic. The scalar kernel (the fallback of builds without
// AVX-512, and PgsColoredDef::simd = false) performs per lane exactly the operations of the
// vector kernel, which are those of "pgs"'s contact block: r = (b + fma(j0,a0,j1·a1)) +
// (fma(j2,a2,j3·b0) + fma(j4,b1,j5·b2)); the clamps max(y,0), max(0,λ_n), clamp(y,−t,t)
// written as the compare-and-select of std::max/std::min (same result for ±0 and NaN). So
// both paths and all thread counts give bit-identical iterates.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#if defined(__AVX512F__)
#include <immintrin.h>
#define DC_PGS_COLORED_AVX512 1
#endif
#if defined(_OPENMP)
#include <omp.h>
#endif

#include "dc/engine/pgs_colored.hpp"
#include "lcp/contact_coloring.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc {
namespace {

using solvers::check_input;
using solvers::finish;
using solvers::run_sweeps;

constexpr int W = 8;        // lanes per batch (AVX-512: 8 doubles)
constexpr int kStride = 4;  // doubles per body in Δu (v_x, v_y, ω, padding)

struct alignas(64) Batch {
  double jn[6][W], mjn[6][W], jt[6][W], mjt[6][W];  // J_i/A_ii and M⁻¹J_iᵀΔt per slot
  double bn[W], bt[W], mu[W];                       // b_i/A_ii [N], μ
  std::int32_t la[W], lb[W];                        // Δu offsets (4·body; zero body if absent)
  std::int32_t sa[W], sb[W];                        // Δu offsets written, −1 if absent
  std::uint8_t ka[W], kb[W];                        // 0xF when sa/sb ≥ 0, else 0 (SIMD store masks)
  int count = 0;                                    // lanes in use (the rest: zero padding)
};
static_assert(sizeof(Batch) % 64 == 0);

/// Batches [begin, end) of one colour (independent: may run in any order or in parallel),
/// or of the overflow set (serial = true: one contact per batch, in order).
struct Range {
  int begin, end;
  bool serial;
};

struct Prepared {
  std::vector<Batch> batches;
  std::vector<Range> ranges;
  std::vector<int> row_of;  // permuted slot → LCP row (−1: padding or no tangent row)
  int body_entries = 0;     // kStride·bodies; the zero body follows
};

/// One packed row (slot order: body a v_x, v_y, ω, body b v_x, v_y, ω), as pgs's pack_row.
struct Packed {
  std::array<double, 6> j{}, mj{};
  double b = 0.0;
  bool ok = false;  // acts only on its contact's bodies and A_ii > 0
};

Packed pack(const LcpProblem& p, int i, int a, int bb) {
  Packed r;
  for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) {
    const int col = static_cast<int>(it.col());
    const int off = 3 * (col / 3), comp = col % 3;
    if (off == a) {
      r.j[static_cast<size_t>(comp)] += it.value();
    } else if (bb >= 0 && off == bb) {
      r.j[static_cast<size_t>(3 + comp)] += it.value();
    } else {
      return r;
    }
  }
  double diag = 0.0;
  for (int s = 0; s < 6; ++s) {
    const int off = s < 3 ? a : bb;
    if (off < 0) continue;
    r.mj[static_cast<size_t>(s)] = r.j[static_cast<size_t>(s)] * p.inv_mass[off + s % 3] * p.dt;
    diag += r.j[static_cast<size_t>(s)] * r.mj[static_cast<size_t>(s)];
  }
  const double inv = 1.0 / diag;
  if (!(diag > 0 && std::isfinite(inv))) return r;
  for (double& v : r.j) v *= inv;
  r.b = p.b[i] * inv;
  r.ok = true;
  return r;
}

/// Packs the problem into batches in colour order. Returns an error (the reason "pgs" runs
/// instead) when a contact is not a plain normal row [0, ∞) (+ its tangent row) on its two
/// bodies with A_ii > 0.
std::string prepare(const LcpProblem& p, ContactColorer& colorer, Prepared& out) {
  const ContactConstraints& cons = p.constraints;
  if (cons.empty() || cons.rows() != p.rows()) return "no contact constraints";
  const int bodies = static_cast<int>(p.J.cols() / 3) + (p.J.cols() % 3 != 0 ? 1 : 0);
  out.body_entries = kStride * bodies;
  const int zero = out.body_entries;
  std::vector<std::uint8_t> dynamic(static_cast<size_t>(bodies), 0);
  for (int k = 0; k < bodies; ++k)
    for (int c = 3 * k; c < std::min<int>(3 * k + 3, static_cast<int>(p.inv_mass.size())); ++c)
      if (p.inv_mass[c] != 0.0) dynamic[static_cast<size_t>(k)] = 1;
  for (int c = 0; c < cons.size(); ++c) {
    const int i = cons[c].normal_row;
    if (p.is_friction_row(i) || p.lo[i] != 0.0 || p.hi[i] != std::numeric_limits<double>::infinity())
      return "contact " + std::to_string(c) + "'s normal row has bounds other than [0, inf)";
  }
  const ContactColoring& col = colorer.color(cons, dynamic);

  // Contacts per colour (counting sort, contact order kept inside a colour), overflow last.
  const int nc = cons.size(), ncol = col.colors;
  std::vector<int> start(static_cast<size_t>(ncol) + 2, 0);
  auto slot_of = [&](int colour) { return colour == ContactColoring::kOverflow ? ncol : colour; };
  for (int c = 0; c < nc; ++c) ++start[static_cast<size_t>(slot_of(col.color[static_cast<size_t>(c)])) + 1];
  for (int k = 0; k <= ncol; ++k) start[static_cast<size_t>(k) + 1] += start[static_cast<size_t>(k)];
  std::vector<int> order(static_cast<size_t>(nc));
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int c = 0; c < nc; ++c)
      order[static_cast<size_t>(fill[static_cast<size_t>(slot_of(col.color[static_cast<size_t>(c)]))]++)] = c;
  }
  size_t nbatch = static_cast<size_t>(col.overflow);
  for (int k = 0; k < ncol; ++k)
    nbatch += static_cast<size_t>((start[static_cast<size_t>(k) + 1] - start[static_cast<size_t>(k)] + W - 1) / W);
  out.batches.assign(nbatch, Batch{});
  out.row_of.assign(nbatch * 2 * W, -1);
  out.ranges.clear();

  int b = 0;
  auto put = [&](int c, Batch& B, int lane) -> std::string {
    const ContactConstraint& k = cons[c];
    const int first = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
    const int second = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
    const int a = 3 * first, bb = second < 0 ? -1 : 3 * second;  // columns of J
    const int ua = kStride * first, ub = second < 0 ? -1 : kStride * second;  // entries of Δu
    const Packed n = pack(p, k.normal_row, a, bb);
    if (!n.ok) return "contact " + std::to_string(c) + "'s normal row is singular or acts on another body";
    Packed t;
    if (k.has_friction()) {
      t = pack(p, k.tangent_row, a, bb);
      if (!t.ok) return "contact " + std::to_string(c) + "'s tangent row is singular or acts on another body";
    }
    for (int s = 0; s < 6; ++s) {
      B.jn[s][lane] = n.j[static_cast<size_t>(s)];
      B.mjn[s][lane] = n.mj[static_cast<size_t>(s)];
      B.jt[s][lane] = t.j[static_cast<size_t>(s)];
      B.mjt[s][lane] = t.mj[static_cast<size_t>(s)];
    }
    B.bn[lane] = n.b;
    B.bt[lane] = t.b;
    B.mu[lane] = k.has_friction() ? k.mu : 0.0;
    const bool da = dynamic[static_cast<size_t>(first)] != 0, db = second >= 0 && dynamic[static_cast<size_t>(second)] != 0;
    B.la[lane] = da ? ua : zero;
    B.lb[lane] = db ? ub : zero;
    B.sa[lane] = da ? ua : -1;
    B.sb[lane] = db ? ub : -1;
    B.ka[lane] = da ? 0xF : 0;
    B.kb[lane] = db ? 0xF : 0;
    B.count = lane + 1;
    const size_t base = static_cast<size_t>(&B - out.batches.data()) * 2 * W;
    out.row_of[base + static_cast<size_t>(lane)] = k.normal_row;
    out.row_of[base + W + static_cast<size_t>(lane)] = k.tangent_row;
    return {};
  };
  for (int k = 0; k <= ncol; ++k) {
    const int s0 = start[static_cast<size_t>(k)], s1 = start[static_cast<size_t>(k) + 1];
    if (s1 == s0) continue;
    const bool overflow = k == ncol;
    const int first_batch = b;
    for (int s = s0; s < s1;) {
      Batch& B = out.batches[static_cast<size_t>(b)];
      for (int r = 0; r < W; ++r) {  // padding lanes: zero coefficients, zero body, no stores
        B.la[r] = B.lb[r] = zero;
        B.sa[r] = B.sb[r] = -1;
        B.ka[r] = B.kb[r] = 0;
      }
      for (int lane = 0; lane < (overflow ? 1 : W) && s < s1; ++lane, ++s) {
        if (std::string err = put(order[static_cast<size_t>(s)], B, lane); !err.empty()) return err;
      }
      ++b;
    }
    out.ranges.push_back({first_batch, b, overflow});
  }
  return {};
}

// std::max(a, b) and std::min(a, b) as the vector kernel writes them (compare + select).
inline double max_of(double a, double b) { return (a < b) ? b : a; }
inline double min_of(double a, double b) { return (b < a) ? b : a; }

#if defined(__x86_64__) && !defined(__FMA__) && defined(__GNUC__)
#define DC_PGS_FMA_CLONES __attribute__((target_clones("fma", "default")))
#else
#define DC_PGS_FMA_CLONES
#endif

struct Acc {
  double theta = 0.0;
  bool bad = false;
};

/// Scalar kernel: batches [b0, b1), lane by lane (contacts in slot order).
[[gnu::optimize("no-tree-slp-vectorize")]] DC_PGS_FMA_CLONES void sweep_scalar(
    const Batch* __restrict batches, int b0, int b1, double* __restrict lam, double* __restrict u, Acc& acc) {
  double theta = acc.theta;
  bool bad = acc.bad;
  for (int bi = b0; bi < b1; ++bi) {
    const Batch& B = batches[bi];
    double* ln = lam + static_cast<size_t>(bi) * 2 * W;
    double* lt = ln + W;
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
        const double old = ln[k];
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
        const double old = lt[k];
        const double t = B.mu[k] * max_of(0.0, xn);
        const double y = old - res;
        const double c = min_of(max_of(y, -t), t);
        const bool active = 0.0 < t;
        const double x = active ? c : 0.0;
        bad |= !std::isfinite(active ? x : y);
        const double d = x - old;
        lt[k] = x;
        a0 = std::fma(B.mjt[0][k], d, a0);
        a1 = std::fma(B.mjt[1][k], d, a1);
        a2 = std::fma(B.mjt[2][k], d, a2);
        v0 = std::fma(B.mjt[3][k], d, v0);
        v1 = std::fma(B.mjt[4][k], d, v1);
        v2 = std::fma(B.mjt[5][k], d, v2);
        theta = max_of(theta, std::abs(d));
      }
      if (B.sa[k] >= 0) {
        double* sa = u + B.sa[k];
        sa[0] = a0;
        sa[1] = a1;
        sa[2] = a2;
      }
      if (B.sb[k] >= 0) {
        double* sb = u + B.sb[k];
        sb[0] = v0;
        sb[1] = v1;
        sb[2] = v2;
      }
    }
  }
  acc.theta = theta;
  acc.bad = bad;
}

#if DC_PGS_COLORED_AVX512
/// Loads the bodies at Δu offsets off[0..7] (4 doubles each, 32-byte aligned) and
/// transposes them: x = (v_x of the 8 lanes), y = (v_y …), w = (ω …).
inline void load_bodies(const double* __restrict u, const std::int32_t* off, __m512d& x, __m512d& y, __m512d& w) {
  auto row = [&](int k) { return _mm256_loadu_pd(u + off[k]); };
  const __m512d z0 = _mm512_insertf64x4(_mm512_castpd256_pd512(row(0)), row(4), 1);  // b0 | b4
  const __m512d z1 = _mm512_insertf64x4(_mm512_castpd256_pd512(row(1)), row(5), 1);
  const __m512d z2 = _mm512_insertf64x4(_mm512_castpd256_pd512(row(2)), row(6), 1);
  const __m512d z3 = _mm512_insertf64x4(_mm512_castpd256_pd512(row(3)), row(7), 1);
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

/// The inverse of load_bodies: writes (x_k, y_k, w_k, 0) to u + off[k] where mask[k] = 0xF.
inline void store_bodies(double* __restrict u, const std::int32_t* off, const std::uint8_t* mask, __m512d x, __m512d y,
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
  auto put = [&](int k, __m256d v) {
    _mm256_mask_storeu_pd(u + off[k], static_cast<__mmask8>(mask[k]), v);
  };
  put(0, _mm512_castpd512_pd256(r02));
  put(2, _mm512_extractf64x4_pd(r02, 1));
  put(1, _mm512_castpd512_pd256(r13));
  put(3, _mm512_extractf64x4_pd(r13, 1));
  put(4, _mm512_castpd512_pd256(r46));
  put(6, _mm512_extractf64x4_pd(r46, 1));
  put(5, _mm512_castpd512_pd256(r57));
  put(7, _mm512_extractf64x4_pd(r57, 1));
}

/// AVX-512 kernel: batches [b0, b1), 8 lanes at a time, the scalar kernel's operations per lane.
void sweep_avx512(const Batch* __restrict batches, int b0, int b1, double* __restrict lam, double* __restrict u,
                  Acc& acc) {
  const __m512d zero = _mm512_setzero_pd();
  const __m512d inf = _mm512_set1_pd(std::numeric_limits<double>::infinity());
  const __m512d sign = _mm512_set1_pd(-0.0);
  __m512d theta = _mm512_set1_pd(acc.theta);
  __mmask8 bad = 0;
  auto absv = [&](__m512d x) { return _mm512_andnot_pd(sign, x); };
  // Non-finite lanes: |x| ≥ ∞ or NaN (unordered).
  auto nonfinite = [&](__m512d x) { return _mm512_cmp_pd_mask(absv(x), inf, _CMP_NLT_UQ); };
  for (int bi = b0; bi < b1; ++bi) {
    const Batch& B = batches[bi];
    double* ln = lam + static_cast<size_t>(bi) * 2 * W;
    double* lt = ln + W;
    __m512d a0, a1, a2, v0, v1, v2;
    load_bodies(u, B.la, a0, a1, a2);
    load_bodies(u, B.lb, v0, v1, v2);
    auto L = [](const double* x) { return _mm512_load_pd(x); };
    __m512d xn;
    {
      const __m512d s0 = _mm512_fmadd_pd(L(B.jn[0]), a0, _mm512_mul_pd(L(B.jn[1]), a1));
      const __m512d s1 = _mm512_fmadd_pd(L(B.jn[2]), a2, _mm512_mul_pd(L(B.jn[3]), v0));
      const __m512d s2 = _mm512_fmadd_pd(L(B.jn[4]), v1, _mm512_mul_pd(L(B.jn[5]), v2));
      const __m512d res = _mm512_add_pd(_mm512_add_pd(L(B.bn), s0), _mm512_add_pd(s1, s2));
      const __m512d old = _mm512_load_pd(ln);
      const __m512d y = _mm512_sub_pd(old, res);
      xn = _mm512_mask_mov_pd(y, _mm512_cmp_pd_mask(y, zero, _CMP_LT_OQ), zero);  // (y < 0) ? 0 : y
      bad |= nonfinite(xn);
      const __m512d d = _mm512_sub_pd(xn, old);
      _mm512_store_pd(ln, xn);
      a0 = _mm512_fmadd_pd(L(B.mjn[0]), d, a0);
      a1 = _mm512_fmadd_pd(L(B.mjn[1]), d, a1);
      a2 = _mm512_fmadd_pd(L(B.mjn[2]), d, a2);
      v0 = _mm512_fmadd_pd(L(B.mjn[3]), d, v0);
      v1 = _mm512_fmadd_pd(L(B.mjn[4]), d, v1);
      v2 = _mm512_fmadd_pd(L(B.mjn[5]), d, v2);
      theta = _mm512_max_pd(theta, absv(d));
    }
    {
      const __m512d s0 = _mm512_fmadd_pd(L(B.jt[0]), a0, _mm512_mul_pd(L(B.jt[1]), a1));
      const __m512d s1 = _mm512_fmadd_pd(L(B.jt[2]), a2, _mm512_mul_pd(L(B.jt[3]), v0));
      const __m512d s2 = _mm512_fmadd_pd(L(B.jt[4]), v1, _mm512_mul_pd(L(B.jt[5]), v2));
      const __m512d res = _mm512_add_pd(_mm512_add_pd(L(B.bt), s0), _mm512_add_pd(s1, s2));
      const __m512d old = _mm512_load_pd(lt);
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
      _mm512_store_pd(lt, x);
      a0 = _mm512_fmadd_pd(L(B.mjt[0]), d, a0);
      a1 = _mm512_fmadd_pd(L(B.mjt[1]), d, a1);
      a2 = _mm512_fmadd_pd(L(B.mjt[2]), d, a2);
      v0 = _mm512_fmadd_pd(L(B.mjt[3]), d, v0);
      v1 = _mm512_fmadd_pd(L(B.mjt[4]), d, v1);
      v2 = _mm512_fmadd_pd(L(B.mjt[5]), d, v2);
      theta = _mm512_max_pd(theta, absv(d));
    }
    store_bodies(u, B.la, B.ka, a0, a1, a2);
    store_bodies(u, B.lb, B.kb, v0, v1, v2);
  }
  // Horizontal max by hand (GCC 12 warns about an uninitialised temporary inside
  // _mm512_reduce_max_pd); θ ≥ 0, so the order does not matter.
  alignas(64) double lanes[W];
  _mm512_store_pd(lanes, theta);
  double m = lanes[0];
  for (int k = 1; k < W; ++k) m = max_of(m, lanes[k]);
  acc.theta = m;
  acc.bad = acc.bad || bad != 0;
}
#endif

void sweep_batches(const Batch* batches, int b0, int b1, double* lam, double* u, bool simd, Acc& acc) {
#if DC_PGS_COLORED_AVX512
  if (simd) {
    const double before = acc.theta;
    sweep_avx512(batches, b0, b1, lam, u, acc);
    acc.theta = max_of(before, acc.theta);
    return;
  }
#else
  (void)simd;
#endif
  sweep_scalar(batches, b0, b1, lam, u, acc);
}

/// True when no entry of x[0..n) is ±∞ or NaN: an OR over the exponent bits (integer ops, so
/// the compiler vectorises it; Eigen's allFinite took 14 % of a 1000-body sweep).
bool all_finite(const double* x, int n) {
  constexpr std::uint64_t kExp = 0x7ff0000000000000ull;
  std::uint64_t any = 0;
  for (int i = 0; i < n; ++i) {
    std::uint64_t b;
    std::memcpy(&b, x + i, sizeof b);
    any |= static_cast<std::uint64_t>((b & kExp) == kExp);
  }
  return any == 0;
}

class PgsColoredSolver final : public LcpSolver {
 public:
  explicit PgsColoredSolver(const PgsColoredDef& def) : def_(def), colorer_(def.reuse_colors) {}
  [[nodiscard]] std::string name() const override { return "pgs-colored"; }
  [[nodiscard]] bool needs_jacobian() const override { return true; }
  [[nodiscard]] bool needs_assembled_matrix() const override { return false; }

  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) const override {
    Eigen::VectorXd lambda;
    if (p.has_jacobian()) {
      if (auto bad = check_input(p, lambda0, name(), lambda)) return *bad;
    }
    Prepared prep;
    std::string why = p.has_jacobian() ? std::string() : std::string("no Jacobian");
    if (why.empty()) {
      const std::lock_guard<std::mutex> lock(mutex_);
      why = prepare(p, colorer_, prep);
    }
    if (!why.empty()) {
      SolveResult r = solvers::make_pgs_matrix_free()->solve(p, lambda0, o);
      if (r.status != SolveStatus::InvalidInput)
        r.message = "pgs-colored: " + why + ": ran pgs" + (r.message.empty() ? std::string() : "; " + r.message);
      return r;
    }

    // Permuted λ (16 per batch) and Δu = M⁻¹ Jᵀ λ⁰ Δt (kStride per body) and the zero body.
    const int nu = prep.body_entries;
    std::vector<double, Eigen::aligned_allocator<double>> du(static_cast<size_t>(nu + kStride), 0.0);
    {
      const Eigen::VectorXd jt = p.J.transpose() * lambda;
      for (int c = 0; c < jt.size(); ++c)
        du[static_cast<size_t>(kStride * (c / 3) + c % 3)] = p.inv_mass[c] * jt[c] * p.dt;
    }
    const size_t np = prep.row_of.size();
    Eigen::VectorXd lp = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(np));
    for (size_t s = 0; s < np; ++s)
      if (prep.row_of[s] >= 0) lp[static_cast<Eigen::Index>(s)] = lambda[prep.row_of[s]];
    auto unpermute = [&](const Eigen::VectorXd& v) {
      Eigen::VectorXd out = Eigen::VectorXd::Zero(p.rows());
      for (size_t s = 0; s < np; ++s)
        if (prep.row_of[s] >= 0) out[prep.row_of[s]] = v[static_cast<Eigen::Index>(s)];
      return out;
    };
    SolverOptions po = o;
    if (o.on_checkpoint)
      po.on_checkpoint = [&](int k, const Eigen::VectorXd& v) { o.on_checkpoint(k, unpermute(v)); };

    const int threads = effective_threads(static_cast<int>(prep.batches.size()));
    const Batch* batches = prep.batches.data();
    const bool simd = def_.simd;
    SolveResult r = run_sweeps(p, std::move(lp), po, [&](Eigen::VectorXd& l, bool& nonfinite) {
      double* lam = l.data();
      double* u = du.data();
      Acc acc;
      if (threads <= 1) {
        for (const Range& rg : prep.ranges) sweep_batches(batches, rg.begin, rg.end, lam, u, simd, acc);
        if (!all_finite(u, nu)) acc.bad = true;
      } else {
        sweep_parallel(prep, lam, u, nu, simd, threads, acc);  // checks Δu too
      }
      if (!std::isfinite(acc.theta)) acc.bad = true;
      nonfinite = nonfinite || acc.bad;
      return acc.theta;
    });
    r.lambda = unpermute(r.lambda);
    finish(p, r);
    return r;
  }

 private:
  [[nodiscard]] int effective_threads(int batches) const {
#if defined(_OPENMP)
    int t = def_.threads > 0 ? def_.threads : omp_get_max_threads();
    if (t > 1 && batches < def_.min_batches_per_thread * t) t = 1;
    return std::max(1, t);
#else
    (void)batches;
    return 1;
#endif
  }

  /// One sweep on `threads` threads: each colour's batches split statically (contiguous
  /// blocks, so a thread keeps the same region of the pile from colour to colour), a barrier
  /// between colours, the overflow set on one thread. θ and the flag are max/or reductions:
  /// the result does not depend on the thread count. After the last colour each thread checks
  /// its share of Δu[0, nu) for non-finite entries (the serial check cost 1/3 of the serial
  /// per-sweep work at 10,000 bodies).
  static void sweep_parallel(const Prepared& prep, double* lam, double* u, int nu, bool simd, int threads,
                             Acc& acc) {
#if defined(_OPENMP)
    double theta = acc.theta;
    bool bad = acc.bad;
    const Batch* batches = prep.batches.data();
    const int nr = static_cast<int>(prep.ranges.size());
#pragma omp parallel num_threads(threads) reduction(max : theta) reduction(|| : bad)
    {
      Acc local;
      const int tid = omp_get_thread_num(), nt = omp_get_num_threads();
      for (int k = 0; k < nr; ++k) {
        const Range& rg = prep.ranges[static_cast<size_t>(k)];
        if (rg.serial) {
          if (tid == 0) sweep_batches(batches, rg.begin, rg.end, lam, u, simd, local);
        } else {
          const int n = rg.end - rg.begin;
          const int lo = rg.begin + static_cast<int>(static_cast<long>(n) * tid / nt);
          const int hi = rg.begin + static_cast<int>(static_cast<long>(n) * (tid + 1) / nt);
          sweep_batches(batches, lo, hi, lam, u, simd, local);
        }
#pragma omp barrier
      }
      const int u0 = static_cast<int>(static_cast<long>(nu) * tid / nt);
      const int u1 = static_cast<int>(static_cast<long>(nu) * (tid + 1) / nt);
      theta = max_of(theta, local.theta);
      bad = bad || local.bad || !all_finite(u + u0, u1 - u0);
    }
    acc.theta = theta;
    acc.bad = bad;
#else
    (void)threads;
    for (const Range& rg : prep.ranges) sweep_batches(prep.batches.data(), rg.begin, rg.end, lam, u, simd, acc);
    if (!all_finite(u, nu)) acc.bad = true;
#endif
  }

  PgsColoredDef def_;
  // The colouring of the previous solve (reused where contacts persist); guarded so that a
  // solver shared between threads stays correct.
  mutable ContactColorer colorer_;
  mutable std::mutex mutex_;
};

}  // namespace

std::unique_ptr<LcpSolver> make_pgs_colored(const PgsColoredDef& def) { return std::make_unique<PgsColoredSolver>(def); }

bool pgs_colored_has_simd() {
#if DC_PGS_COLORED_AVX512
  return true;
#else
  return false;
#endif
}

namespace solvers {
std::unique_ptr<LcpSolver> make_pgs_colored() { return dc::make_pgs_colored(PgsColoredDef{}); }
}  // namespace solvers

}  // namespace dc
