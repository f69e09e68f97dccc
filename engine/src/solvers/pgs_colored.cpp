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
// row order at checkpoints and at the end. Δu (M⁻¹ Jᵀ λ Δt) keeps "pgs"'s layout, 3 doubles
// per body, followed by a zero body that absent bodies (walls, bodies with M⁻¹ = 0, padding
// lanes) are read from.
//
// Gather/scatter. Box2D v3 stores its float body state padded to 32 bytes and gathers with
// 8 aligned loads + an 8 × 8 transpose. Here a body is 3 doubles and a lane group needs 3
// values × 2 bodies: hardware gathers (vgatherdpd, 6 per batch) and masked scatters
// (vscatterdpd, 6 per batch, lanes of absent bodies masked off, so nothing is written to a
// shared dummy — no false sharing between threads). Bodies of one colour are distinct, so
// the scatters never collide. (Measured in bench/micro_pgs.cpp; see docs/solvers.md.)
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

#include "dc/engine/contact_coloring.hpp"
#include "dc/engine/pgs_colored.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc {
namespace {

using solvers::check_input;
using solvers::finish;
using solvers::run_sweeps;

constexpr int W = 8;  // lanes per batch (AVX-512: 8 doubles)

struct alignas(64) Batch {
  double jn[6][W], mjn[6][W], jt[6][W], mjt[6][W];  // J_i/A_ii and M⁻¹J_iᵀΔt per slot
  double bn[W], bt[W], mu[W];                       // b_i/A_ii [N], μ
  std::int32_t la[W], lb[W];                        // Δu offsets read (zero body if absent)
  std::int32_t sa[W], sb[W];                        // Δu offsets written, −1 if absent
  std::uint8_t ma = 0, mb = 0;                      // lane masks of sa ≥ 0, sb ≥ 0
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
  int body_entries = 0;     // 3·bodies; the zero body follows
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
  out.body_entries = 3 * bodies;
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
    const int a = 3 * first, bb = second < 0 ? -1 : 3 * second;
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
    B.la[lane] = da ? a : zero;
    B.lb[lane] = db ? bb : zero;
    B.sa[lane] = da ? a : -1;
    B.sb[lane] = db ? bb : -1;
    if (da) B.ma = static_cast<std::uint8_t>(B.ma | (1u << lane));
    if (db) B.mb = static_cast<std::uint8_t>(B.mb | (1u << lane));
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
    const __m256i la = _mm256_load_si256(reinterpret_cast<const __m256i*>(B.la));
    const __m256i lb = _mm256_load_si256(reinterpret_cast<const __m256i*>(B.lb));
    __m512d a0 = _mm512_i32gather_pd(la, u + 0, 8);
    __m512d a1 = _mm512_i32gather_pd(la, u + 1, 8);
    __m512d a2 = _mm512_i32gather_pd(la, u + 2, 8);
    __m512d v0 = _mm512_i32gather_pd(lb, u + 0, 8);
    __m512d v1 = _mm512_i32gather_pd(lb, u + 1, 8);
    __m512d v2 = _mm512_i32gather_pd(lb, u + 2, 8);
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
    const __m256i sa = _mm256_load_si256(reinterpret_cast<const __m256i*>(B.sa));
    const __m256i sb = _mm256_load_si256(reinterpret_cast<const __m256i*>(B.sb));
    _mm512_mask_i32scatter_pd(u + 0, B.ma, sa, a0, 8);
    _mm512_mask_i32scatter_pd(u + 1, B.ma, sa, a1, 8);
    _mm512_mask_i32scatter_pd(u + 2, B.ma, sa, a2, 8);
    _mm512_mask_i32scatter_pd(u + 0, B.mb, sb, v0, 8);
    _mm512_mask_i32scatter_pd(u + 1, B.mb, sb, v1, 8);
    _mm512_mask_i32scatter_pd(u + 2, B.mb, sb, v2, 8);
  }
  acc.theta = _mm512_reduce_max_pd(theta);
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

    // Permuted λ (16 per batch) and Δu = M⁻¹ Jᵀ λ⁰ Δt followed by the zero body.
    const int nu = prep.body_entries;
    std::vector<double> du(static_cast<size_t>(nu + 3), 0.0);
    {
      const Eigen::VectorXd jt = p.J.transpose() * lambda;
      for (int c = 0; c < jt.size(); ++c) du[static_cast<size_t>(c)] = p.inv_mass[c] * jt[c] * p.dt;
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
      } else {
        sweep_parallel(prep, lam, u, simd, threads, acc);
      }
      if (!std::isfinite(acc.theta) || !Eigen::Map<const Eigen::VectorXd>(u, nu).allFinite()) acc.bad = true;
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
  /// the result does not depend on the thread count.
  static void sweep_parallel(const Prepared& prep, double* lam, double* u, bool simd, int threads, Acc& acc) {
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
      theta = max_of(theta, local.theta);
      bad = bad || local.bad;
    }
    acc.theta = theta;
    acc.bad = bad;
#else
    (void)threads;
    for (const Range& rg : prep.ranges) sweep_batches(prep.batches.data(), rg.begin, rg.end, lam, u, simd, acc);
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
