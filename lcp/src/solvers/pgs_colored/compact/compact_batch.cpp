// pgs-colored's compact batches (compact_batch.hpp): the direct packing and the compression, each
// with its bitwise check, and the scalar kernel on them.
#include "solvers/pgs_colored/compact/compact_batch.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/pgs_colored_pack_simd.hpp"
#include "solvers/pgs_colored/relax/over_relaxation.hpp"

namespace dc::colored {
namespace {

inline std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

/// The bits of expand()'s derived value: 0 − x (negate) or x where `on`, else +0.
inline std::uint64_t derived(bool on, bool negate, double x) { return on ? bits(negate ? 0.0 - x : x) : 0; }

/// The lanes of one batch as pack_direct packs them: rows, J columns (lane_rows'), μ and λ⁰ of
/// the normal and tangent rows (padding lanes: lane 0's contact, λ⁰ unused).
struct DirectLanes {
  int rn[W], rt[W], a[W], bb[W];
  double mu[W], ln[W], lt[W];
};

/// pack_direct's sources from the problem: false when a lane has no friction.
bool lanes_from_rows(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, const Prepared& out, int s0,
                     int lanes, DirectLanes& d) {
  const int* order = out.order.data() + s0;
  if (!lane_rows(p, order, lanes, d.rn, d.rt, d.a, d.bb)) return false;
  for (int lane = 0; lane < W; ++lane) {
    d.mu[lane] = p.constraints[order[lane < lanes ? lane : 0]].mu;
    d.ln[lane] = lambda[d.rn[lane]];
    d.lt[lane] = lambda[d.rt[lane]];
  }
  return true;
}

/// pack_direct's sources from the staged records (stage_sources), packed by pack_compact_staged:
/// false when a lane's record is not usable or without AVX2.
bool pack_from_staged(const LcpProblem& p, const Prepared& out, int s0, int lanes, double omega, CompactBatch& C,
                      DirectLanes& d, double* diag_n, double* diag_t, unsigned& singular, unsigned& two,
                      unsigned& fric, bool& exact) {
  constexpr int kRecord = sizeof(StagedRows) / sizeof(double);
  int on[W], ot[W];
  alignas(64) double bn[W], bt[W];
  const StagedRows* st = out.staged.data();
  for (int lane = 0; lane < W; ++lane) {
    const int q = s0 + (lane < lanes ? lane : 0);
    if (out.usable[static_cast<size_t>(q)] == 0) return false;
    const StagedRows& r = st[q];
    d.a[lane] = r.a;
    d.bb[lane] = r.bb;
    d.rn[lane] = r.rn;
    d.rt[lane] = r.rt;
    d.mu[lane] = r.mu;
    d.ln[lane] = r.ln;
    d.lt[lane] = r.lt;
    on[lane] = q * kRecord;
    ot[lane] = q * kRecord + 6;
    bn[lane] = r.bn;
    bt[lane] = r.bt;
  }
  return pack_compact_staged(st[0].vn, on, ot, bn, bt, d.a, d.bb, p.inv_mass.data(), p.dt, omega, C, diag_n, diag_t,
                             singular, two, fric, exact, out.wide_pack);
}

/// fill_compact's direct path: batch bi's rows packed straight into out.compact[bi]
/// (pack_compact_simd, or pack_compact_staged from the staged sources when stage_sources staged
/// the problem) when every lane has friction and rows in the usual storage and no row is
/// singular (fill_batch names the failure); false when not taken. exact: the batch is complete
/// (bodies, padding, A_ii, λ⁰ written); else the caller packs the full batch.
bool pack_direct(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out, int bi,
                 double* lp, double* other, double omega, bool& exact) {
  const int slot = out.slot_of_batch[static_cast<size_t>(bi)];
  int s0 = 0, lanes = 0;
  lanes_of(out, slot, bi - out.batch_of[static_cast<size_t>(slot)], s0, lanes);
  if (lanes <= 0) return false;
  CompactBatch& C = out.compact[static_cast<size_t>(bi)];
  DirectLanes d;
  double diag_n[W], diag_t[W];
  unsigned singular = 0, two = 0, fric = 0;
  if (out.staged_now) {
    if (!pack_from_staged(p, out, s0, lanes, omega, C, d, diag_n, diag_t, singular, two, fric, exact)) return false;
  } else {
    if (!lanes_from_rows(p, lambda, out, s0, lanes, d)) return false;  // (padding lanes cleared below)
    if (!pack_compact_simd(p, d.rn, d.rt, d.a, d.bb, omega, C, diag_n, diag_t, singular, two, fric, exact,
                           out.wide_pack))
      return false;
  }
  const unsigned used = (1u << lanes) - 1u;
  if ((singular & used) != 0) return false;
  if (!exact) return true;
  int* row_of = out.row_of.data() + static_cast<size_t>(bi) * 2 * W;
  for (int lane = 0; lane < lanes; ++lane)
    put_lane(out, C, row_of, lane, d.a[lane] / 3, d.bb[lane] < 0 ? -1 : d.bb[lane] / 3, d.mu[lane], d.rn[lane],
             d.rt[lane]);
  for (int lane = lanes; lane < W; ++lane) {  // padding: fill_batch's zero rows, zero body, A_ii = 1
    for (int q = 0; q < 4; ++q) C.jn[q][lane] = C.jt[q][lane] = 0.0;
    for (int s = 0; s < 6; ++s) C.mjn[s][lane] = 0.0;
    C.mjt[0][lane] = C.mjt[1][lane] = 0.0;
    C.bn[lane] = C.bt[lane] = C.mu[lane] = 0.0;
    C.la[lane] = C.lb[lane] = out.body_entries;
    C.ka[lane] = C.kb[lane] = 0;
    row_of[lane] = row_of[W + lane] = -1;
    diag_n[lane] = diag_t[lane] = 1.0;
  }
  C.two = static_cast<std::uint8_t>(two & used);
  C.fric = static_cast<std::uint8_t>(fric & used);
  C.count = lanes;
  const size_t s0p = static_cast<size_t>(bi) * 2 * W;
  std::copy(diag_n, diag_n + W, out.diag.data() + s0p);
  std::copy(diag_t, diag_t + W, out.diag.data() + s0p + W);
  for (int lane = 0; lane < W; ++lane) {
    lp[s0p + lane] = other[s0p + lane] = lane < lanes ? d.ln[lane] : 0.0;
    lp[s0p + W + lane] = other[s0p + W + lane] = lane < lanes ? d.lt[lane] : 0.0;
  }
  return true;
}

}  // namespace

bool compress(const Batch& B, CompactBatch& C) {
  constexpr int kept[4] = {0, 1, 2, 5};
  for (int q = 0; q < 4; ++q) {
    std::memcpy(C.jn[q], B.jn[kept[q]], sizeof(C.jn[q]));
    std::memcpy(C.jt[q], B.jt[kept[q]], sizeof(C.jt[q]));
  }
  std::memcpy(C.mjn, B.mjn, sizeof(C.mjn));
  std::memcpy(C.mjt[0], B.mjt[2], sizeof(C.mjt[0]));
  std::memcpy(C.mjt[1], B.mjt[5], sizeof(C.mjt[1]));
  std::memcpy(C.bn, B.bn, sizeof(C.bn));
  std::memcpy(C.bt, B.bt, sizeof(C.bt));
  std::memcpy(C.mu, B.mu, sizeof(C.mu));
  std::memcpy(C.la, B.la, sizeof(C.la));
  std::memcpy(C.lb, B.lb, sizeof(C.lb));
  std::memcpy(C.ka, B.ka, sizeof(C.ka));
  std::memcpy(C.kb, B.kb, sizeof(C.kb));
  C.count = B.count;
  // Per lane: the derived slots hold +0 (one body; no friction; padding: the bit clear) or the
  // derivation (the bit set); every derived slot is compared bit for bit with expand()'s value.
  std::uint8_t two = 0, fric = 0;
  std::uint64_t differ = 0;
  for (int k = 0; k < W; ++k) {
    const bool t = (bits(B.jn[3][k]) | bits(B.jn[4][k]) | bits(B.jt[3][k]) | bits(B.jt[4][k])) != 0;
    const bool f = (bits(B.mjt[0][k]) | bits(B.mjt[1][k]) | bits(B.mjt[3][k]) | bits(B.mjt[4][k])) != 0;
    two = static_cast<std::uint8_t>(two | (t ? 1u << k : 0u));
    fric = static_cast<std::uint8_t>(fric | (f ? 1u << k : 0u));
    differ |= bits(B.jn[3][k]) ^ derived(t, true, B.jn[0][k]);
    differ |= bits(B.jn[4][k]) ^ derived(t, true, B.jn[1][k]);
    differ |= bits(B.jt[3][k]) ^ derived(t, true, B.jt[0][k]);
    differ |= bits(B.jt[4][k]) ^ derived(t, true, B.jt[1][k]);
    differ |= bits(B.mjt[0][k]) ^ derived(f, true, B.mjn[1][k]);
    differ |= bits(B.mjt[1][k]) ^ derived(f, false, B.mjn[0][k]);
    differ |= bits(B.mjt[3][k]) ^ derived(f, true, B.mjn[4][k]);
    differ |= bits(B.mjt[4][k]) ^ derived(f, false, B.mjn[3][k]);
  }
  C.two = two;
  C.fric = fric;
  return differ == 0;
}

bool fill_compact(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out, int bi,
                  double* lp, double* other, double omega, bool full) {
  Batch& B = out.batches[static_cast<size_t>(bi)];
  if (full) {
    fill_batch(p, lambda, out, bi, lp, other);
    if (omega != 1.0) over_relax(B, omega);
    return false;
  }
  bool exact = false;
  if (pack_direct(p, lambda, out, bi, lp, other, omega, exact)) {
    if (exact) return true;
    fill_batch(p, lambda, out, bi, lp, other);
    if (omega != 1.0) over_relax(B, omega);
    return false;
  }
  Batch local;  // in cache: only the compact batch goes to memory
  fill_batch(p, lambda, out, bi, lp, other, &local);
  if (omega != 1.0) over_relax(local, omega);
  if (compress(local, out.compact[static_cast<size_t>(bi)])) return true;
  B = local;
  return false;
}

void sweep_compact_scalar(const CompactBatch* batches, int b0, int b1, const double* in, double* out, double* u,
                          Acc& acc) {
  Batch B;
  for (int bi = b0; bi < b1; ++bi) {
    expand(batches[bi], B);
    sweep_scalar(&B, 0, 1, in + static_cast<long>(bi) * 2 * W, out + static_cast<long>(bi) * 2 * W, u, acc);
  }
}

}  // namespace dc::colored
