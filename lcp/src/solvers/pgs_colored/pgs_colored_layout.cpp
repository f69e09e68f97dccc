// The set-up of "pgs-colored" (pgs_colored_layout.hpp): the manifold pairs, the order of the
// contacts by colour, and the packing of rows into single and pair batches.
#include "solvers/pgs_colored/pgs_colored_layout.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <time.h>

#include "dc/core/work_team.hpp"
#include "solvers/pgs_colored/pgs_colored_pack_simd.hpp"
#include "solvers/pgs_colored/setup/layout_scan.hpp"
#include "solvers/pgs_manifold_block.hpp"

namespace dc::colored {
namespace {

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// pack_row's usual case: the row's N (3: one body, 6: two) entries v in slot order, on the
/// bodies at columns a and bb; the same operations in the same order as pack_row's general
/// loop, on scalars held in registers (an array here is written as a vector and read back lane
/// by lane, which stalls the loads on forwarding).
template <int N>
inline void pack_usual(const double* v, const double* im, int a, int bb, double dt, double (*j)[W], double (*mj)[W],
                       int lane, double& d) {
  double sum = 0.0;
#pragma GCC unroll 6
  for (int s = 0; s < N; ++s) {
    const double r = 0.0 + v[s];
    const double m = r * im[s < 3 ? a + s : bb + s - 3] * dt;
    sum += r * m;
    j[s][lane] = r;
    mj[s][lane] = m;
  }
#pragma GCC unroll 3
  for (int s = N; s < 6; ++s) j[s][lane] = mj[s][lane] = 0.0;
  d = sum;
}

/// Packs row i of J on the bodies at J columns a (slots 0–2) and bb (slots 3–5; −1 absent) into
/// lane `lane` of j/mj, unscaled: j = J_i, mj = M⁻¹ J_iᵀ Δt, b = b_i, diag = A_ii (summed in slot
/// order as "pgs"'s pack_row); scale_rows divides by A_ii afterwards, 8 lanes at once. False
/// when the row acts on another body.
bool pack_row(const LcpProblem& p, int i, int a, int bb, double (*j)[W], double (*mj)[W], double* b, double* diag,
              int lane) {
  // The usual storage (what the engine assembles): the columns a, a+1, a+2 (, bb, bb+1, bb+2)
  // once each, in order; then each r_s is 0 + J_is, as the general loop below sums it (−0 → +0).
  const double* value = p.J.valuePtr();
  const int q0 = p.J.outerIndexPtr()[i];
  const int n = (p.J.isCompressed() ? p.J.outerIndexPtr()[i + 1] : q0 + p.J.innerNonZeroPtr()[i]) - q0;
  const int* col = p.J.innerIndexPtr() + q0;
  if (n == (bb < 0 ? 3 : 6) && col[0] == a && col[1] == a + 1 && col[2] == a + 2 &&
      (bb < 0 || (col[3] == bb && col[4] == bb + 1 && col[5] == bb + 2))) {
    if (bb < 0)
      pack_usual<3>(value + q0, p.inv_mass.data(), a, bb, p.dt, j, mj, lane, diag[lane]);
    else
      pack_usual<6>(value + q0, p.inv_mass.data(), a, bb, p.dt, j, mj, lane, diag[lane]);
    b[lane] = p.b[i];
    return true;
  }
  double r[6] = {0, 0, 0, 0, 0, 0};
  for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) {
    const int c = static_cast<int>(it.col());
    if (c >= a && c < a + 3) {
      r[c - a] += it.value();
    } else if (bb >= 0 && c >= bb && c < bb + 3) {
      r[3 + c - bb] += it.value();
    } else {
      return false;
    }
  }
  const double* im = p.inv_mass.data();
  double d = 0.0;
  for (int s = 0; s < 6; ++s) {
    const int off = s < 3 ? a : bb;
    const double m = off < 0 ? 0.0 : r[s] * im[off + s % 3] * p.dt;
    if (off >= 0) d += r[s] * m;
    j[s][lane] = r[s];
    mj[s][lane] = m;
  }
  b[lane] = p.b[i];
  diag[lane] = d;
  return true;
}

/// j ← j/A_ii and b ← b/A_ii on all lanes (padding lanes: A_ii = 1, zero rows); false when a
/// lane's A_ii is not finite and > 0 or 1/A_ii is not finite. The same products as a lane-by-lane
/// scaling. A finite A_ii = Σ_s r_s·(r_s·M⁻¹_s·Δt) implies finite J entries in its row (an
/// infinite or NaN r_s makes its term ∞ or NaN: M⁻¹ ≥ 0, Δt > 0), so a packing that succeeds has
/// checked values_finite (pgs_colored_residual.hpp) on every row.
bool scale_rows(double (*j)[W], double* b, const double* diag) {
  double inv[W];
  bool ok = true;
  for (int lane = 0; lane < W; ++lane) {
    inv[lane] = 1.0 / diag[lane];
    ok &= diag[lane] > 0 && std::isfinite(diag[lane]) && std::isfinite(inv[lane]);
  }
  for (int s = 0; s < 6; ++s)
    for (int lane = 0; lane < W; ++lane) j[s][lane] *= inv[lane];
  for (int lane = 0; lane < W; ++lane) b[lane] *= inv[lane];
  return ok;
}

/// The rows of one contact in a lane: normal and tangent coefficients, b, μ.
struct RowSet {
  double (*jn)[W];
  double (*mjn)[W];
  double (*jt)[W];
  double (*mjt)[W];
  double *bn, *bt, *mu;
};

/// Packs contact c into lane `lane` of rs (rows unscaled, see pack_row), its bodies' Δu offsets
/// into la/lb and store flags into ka/kb, its rows into row_n/row_t; false when one of its rows
/// acts on another body.
bool pack_contact(const LcpProblem& p, const Prepared& out, int zero, int c, const RowSet& rs,
                  std::int32_t* la, std::int32_t* lb, std::uint8_t* ka, std::uint8_t* kb, int lane, int* row_n,
                  int* row_t, double* diag_n, double* diag_t) {
  const ContactConstraint& k = p.constraints[c];
  const int first = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
  const int second = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
  const int a = 3 * first, bb = second < 0 ? -1 : 3 * second;  // columns of J
  if (!pack_row(p, k.normal_row, a, bb, rs.jn, rs.mjn, rs.bn, diag_n, lane)) return false;
  if (k.has_friction()) {
    if (!pack_row(p, k.tangent_row, a, bb, rs.jt, rs.mjt, rs.bt, diag_t, lane)) return false;
    rs.mu[lane] = k.mu;
  } else {
    for (int s = 0; s < 6; ++s) rs.jt[s][lane] = rs.mjt[s][lane] = 0.0;
    rs.bt[lane] = rs.mu[lane] = 0.0;
    diag_t[lane] = 1.0;
  }
  const bool da = out.dynamic[static_cast<size_t>(first)] != 0;
  const bool db = second >= 0 && out.dynamic[static_cast<size_t>(second)] != 0;
  la[lane] = da ? out.du_entry(first) : zero;
  lb[lane] = db ? out.du_entry(second) : zero;
  ka[lane] = da ? 1 : 0;
  kb[lane] = db ? 1 : 0;
  row_n[lane] = k.normal_row;
  row_t[lane] = k.tangent_row;
  return true;
}

/// fill_batch's rows and bodies of a batch of `lanes` contacts with friction from ordered
/// position s0 by pack_rows_simd, scaled (the padding lanes computed on lane 0's rows, then
/// cleared by the caller's pad_rows and pad_bodies); ok_n / ok_t as scale_rows's. False when a
/// contact has no friction or a row not in the usual storage (then the batch is packed lane by
/// lane).
bool pack_batch_simd(const LcpProblem& p, const Prepared& out, int s0, int lanes, Batch& B, int* row_of,
                     double* diag_n, double* diag_t, bool& ok_n, bool& ok_t) {
  if (!simd_pack_available()) return false;
  int rn[W], rt[W], a[W], bb[W];
  const int* order = out.order.data() + s0;
  if (!lane_rows(p, order, lanes, rn, rt, a, bb)) return false;
  unsigned singular_n = 0, singular_t = 0;
  if (!pack_rows_simd(p, rn, a, bb, B.jn, B.mjn, B.bn, diag_n, singular_n) ||
      !pack_rows_simd(p, rt, a, bb, B.jt, B.mjt, B.bt, diag_t, singular_t))
    return false;
  for (int lane = 0; lane < lanes; ++lane) {
    const ContactConstraint& k = p.constraints[order[lane]];
    put_lane(out, B, row_of, lane, a[lane] / 3, bb[lane] < 0 ? -1 : bb[lane] / 3, k.mu, k.normal_row, k.tangent_row);
  }
  const unsigned used = (1u << lanes) - 1u;
  ok_n = (singular_n & used) == 0;
  ok_t = (singular_t & used) == 0;
  return true;
}

/// fill_pair's rows, bodies and 2 × 2 blocks of a pair batch of `lanes` manifolds with friction
/// from ordered position s0, as pack_batch_simd for the four rows of each lane; A_01 from the
/// unscaled normal row of point 0 (0 + J_is, 0 in absent slots, as pack_row writes it) and
/// M⁻¹J_1ᵀΔt, summed in slot order as fill_pair does. ok: every lane's A_ii as scale_rows wants.
bool pack_pair_simd(const LcpProblem& p, const Prepared& out, int s0, int lanes, PairBatch& P, int* row_of,
                    double* dn0, double* dt0, double* dn1, double* dt1, bool& ok) {
  if (!simd_pack_available()) return false;
  int rn0[W], rt0[W], rn1[W], rt1[W], a[W], bb[W];
  const int* order = out.order.data() + s0;
  for (int lane = 0; lane < W; ++lane) {
    const int c = order[lane < lanes ? lane : 0];
    const ContactConstraint& k0 = p.constraints[c];
    const ContactConstraint& k1 = p.constraints[out.partner[static_cast<size_t>(c)]];
    if (!k0.has_friction() || !k1.has_friction()) return false;
    const int first = k0.has_body_a() ? std::min(k0.body_a, k0.body_b) : k0.body_b;
    const int second = k0.has_body_a() ? std::max(k0.body_a, k0.body_b) : -1;
    a[lane] = 3 * first;
    bb[lane] = second < 0 ? -1 : 3 * second;
    rn0[lane] = k0.normal_row;
    rt0[lane] = k0.tangent_row;
    rn1[lane] = k1.normal_row;
    rt1[lane] = k1.tangent_row;
  }
  unsigned sn0 = 0, st0 = 0, sn1 = 0, st1 = 0;
  if (!pack_rows_simd(p, rn0, a, bb, P.jn0, P.mjn0, P.bn0, dn0, sn0) ||
      !pack_rows_simd(p, rt0, a, bb, P.jt0, P.mjt0, P.bt0, dt0, st0) ||
      !pack_rows_simd(p, rn1, a, bb, P.jn1, P.mjn1, P.bn1, dn1, sn1) ||
      !pack_rows_simd(p, rt1, a, bb, P.jt1, P.mjt1, P.bt1, dt1, st1))
    return false;
  const int zero = out.body_entries;
  const std::uint8_t* dynamic = out.dynamic.data();
  const double* value = p.J.valuePtr();
  for (int lane = 0; lane < lanes; ++lane) {
    const int c = order[lane];
    const ContactConstraint& k0 = p.constraints[c];
    const ContactConstraint& k1 = p.constraints[out.partner[static_cast<size_t>(c)]];
    const int first = a[lane] / 3, second = bb[lane] < 0 ? -1 : bb[lane] / 3;
    const bool da = dynamic[first] != 0;
    const bool db = second >= 0 && dynamic[second] != 0;
    P.mu0[lane] = k0.mu;
    P.mu1[lane] = k1.mu;
    P.la[lane] = da ? out.du_entry(first) : zero;
    P.lb[lane] = db ? out.du_entry(second) : zero;
    P.ka[lane] = da ? 1 : 0;
    P.kb[lane] = db ? 1 : 0;
    row_of[lane] = k0.normal_row;
    row_of[W + lane] = k0.tangent_row;
    row_of[2 * W + lane] = k1.normal_row;
    row_of[3 * W + lane] = k1.tangent_row;
    const double* v = value + p.J.outerIndexPtr()[rn0[lane]];
    const int n = bb[lane] < 0 ? 3 : 6;
    double a01 = 0.0;
    for (int s = 0; s < 6; ++s) a01 += (s < n ? 0.0 + v[s] : 0.0) * P.mjn1[s][lane];
    const bool block = solvers::manifold_block_conditioned(dn0[lane], dn1[lane], a01);
    P.c01[lane] = a01 / dn0[lane];
    P.c10[lane] = a01 / dn1[lane];
    P.inv_det[lane] = block ? 1.0 / (1.0 - P.c01[lane] * P.c10[lane]) : 0.0;
    P.block[lane] = block ? 1.0 : 0.0;
  }
  const unsigned used = (1u << lanes) - 1u;
  ok = ((sn0 | st0 | sn1 | st1) & used) == 0;
  return true;
}

/// Zero rows for lanes [from, W) of rs (padding).
void pad_rows(const RowSet& rs, int from, int* row_n, int* row_t) {
  for (int lane = from; lane < W; ++lane) {
    for (int s = 0; s < 6; ++s) rs.jn[s][lane] = rs.mjn[s][lane] = rs.jt[s][lane] = rs.mjt[s][lane] = 0.0;
    rs.bn[lane] = rs.bt[lane] = rs.mu[lane] = 0.0;
    row_n[lane] = row_t[lane] = -1;
  }
}

/// The zero body and no stores for lanes [from, W).
void pad_bodies(int from, int zero, std::int32_t* la, std::int32_t* lb, std::uint8_t* ka, std::uint8_t* kb) {
  for (int lane = from; lane < W; ++lane) {
    la[lane] = lb[lane] = zero;
    ka[lane] = kb[lane] = 0;
  }
}

/// Whether scale_rows accepts A_ii = d: finite, > 0, and 1/d finite.
bool regular(double d) { return d > 0 && std::isfinite(d) && std::isfinite(1.0 / d); }

/// Records in `failed` the first of lanes [0, lanes) whose normal or tangent A_ii is not regular.
void name_singular(const Prepared& out, int s0, int lanes, const double* dn, const double* dt, int& failed) {
  for (int lane = 0; lane < lanes && failed < 0; ++lane)
    if (!regular(dn[lane]) || !regular(dt[lane])) failed = out.order[static_cast<size_t>(s0 + lane)];
}

/// fill_pair lane by lane: the rows packed and their blocks formed per lane, then scaled (all
/// padding lanes zero rows, A_ii = 1); returns scale_rows's verdict and records a lane whose rows
/// act on another body in `failed`.
bool fill_pair_lanes(const LcpProblem& p, const Prepared& out, int s0, int lanes, PairBatch& P, int* row_of,
                     double* dn0, double* dt0, double* dn1, double* dt1, int& failed) {
  const int zero = out.body_entries;
  const RowSet r0{P.jn0, P.mjn0, P.jt0, P.mjt0, P.bn0, P.bt0, P.mu0};
  const RowSet r1{P.jn1, P.mjn1, P.jt1, P.mjt1, P.bn1, P.bt1, P.mu1};
  for (int lane = 0; lane < lanes; ++lane) {
    const int c = out.order[static_cast<size_t>(s0 + lane)];
    const int c1 = out.partner[static_cast<size_t>(c)];
    bool ok = pack_contact(p, out, zero, c, r0, P.la, P.lb, P.ka, P.kb, lane, row_of, row_of + W, dn0, dt0);
    ok = ok && pack_contact(p, out, zero, c1, r1, P.la, P.lb, P.ka, P.kb, lane, row_of + 2 * W,
                            row_of + 3 * W, dn1, dt1);
    if (!ok && failed < 0) failed = c;
    // A_01 = J_0 M⁻¹ J_1ᵀ Δt from the unscaled rows, summed in slot order as "pgs" does.
    double a01 = 0.0;
    for (int s = 0; s < 6; ++s) a01 += P.jn0[s][lane] * P.mjn1[s][lane];
    const bool block = ok && solvers::manifold_block_conditioned(dn0[lane], dn1[lane], a01);
    P.c01[lane] = ok ? a01 / dn0[lane] : 0.0;
    P.c10[lane] = ok ? a01 / dn1[lane] : 0.0;
    P.inv_det[lane] = block ? 1.0 / (1.0 - P.c01[lane] * P.c10[lane]) : 0.0;
    P.block[lane] = block ? 1.0 : 0.0;
  }
  pad_rows(r0, lanes, row_of, row_of + W);
  pad_rows(r1, lanes, row_of + 2 * W, row_of + 3 * W);
  pad_bodies(lanes, zero, P.la, P.lb, P.ka, P.kb);
  return scale_rows(P.jn0, P.bn0, dn0) & scale_rows(P.jt0, P.bt0, dt0) & scale_rows(P.jn1, P.bn1, dn1) &
         scale_rows(P.jt1, P.bt1, dt1);
}

/// v ← n copies of x, its storage grown with headroom when too small (assign alone would allocate
/// exactly n, and again whenever n exceeds the last n: each time the colour or batch count rises).
void assign_grown(std::vector<int>& v, size_t n, int x) {
  if (v.capacity() < n) v.reserve(n + n / 2);
  v.assign(n, x);
}

/// out.numbering for a fresh layout of `bodies` bodies: with locality the bodies numbered again
/// when their count changed, the numbering is the identity or BodyNumbering::kRenumberEvery
/// layouts old, and the contacts' key order (returned, sorted on `threads` threads; nullptr,
/// contact order, while the body order was local already); without, slot = body and nullptr:
/// contact order, the last locality numbering set aside (BodyNumbering::kept) for the next
/// locality layout when it has as many bodies (any permutation gives the same bits: a serial
/// probe between threaded solves neither undoes it nor sweeps in its order).
const int* number(const ContactConstraints& cons, int bodies, bool locality, int threads, Prepared& out) {
  BodyNumbering& n = out.numbering;
  if (!locality) {
    // (slot is the identity already while age < 0, local_already or set_aside.)
    const bool renew = n.bodies != bodies;
    if (renew || (n.age >= 0 && !n.local_already && !n.set_aside)) {
      if (!renew) n.kept.swap(n.slot);
      n.set_aside = !renew;
      n.slot.resize(static_cast<size_t>(bodies));
      for (int k = 0; k < bodies; ++k) n.slot[static_cast<size_t>(k)] = k;
    }
    if (renew) {
      n.bodies = bodies;
      n.age = -1;  // (the identity)
    }
    return nullptr;
  }
  if (n.set_aside) {
    n.slot.swap(n.kept);
    n.set_aside = false;
  }
  if (n.bodies != bodies || n.age < 0 || ++n.age >= BodyNumbering::kRenumberEvery) {
    // Where the body order is local already (the Morton internal order: a cut in body index is
    // about as short as one in the breadth-first numbers), keep it and contact order, which
    // follows it, and save the key sort.
    const double identity = cut_share(cons, out.dynamic, bodies, nullptr, n);
    number_bodies(cons, out.dynamic, bodies, n);
    n.local_already = identity <= 2.0 * cut_share(cons, out.dynamic, bodies, n.slot.data(), n) + 0.01;
    if (n.local_already)
      for (int k = 0; k < bodies; ++k) n.slot[static_cast<size_t>(k)] = k;
  }
  if (n.local_already) return nullptr;
  order_by_key(cons, out.dynamic, bodies, n, threads);
  return n.order.data();
}

}  // namespace

std::string layout(const LcpProblem& p, ContactColorer& colorer, OrderedColorer* ordered, int threads,
                   Prepared& out, double* coloring_s, bool locality) {
  const ContactConstraints& cons = p.constraints;
  if (cons.empty() || cons.rows() != p.rows()) return "no contact constraints";
  const int bodies = static_cast<int>(p.J.cols() / 3) + (p.J.cols() % 3 != 0 ? 1 : 0);
  out.body_entries = kStride * bodies;
  out.staged_now = false;  // until stage_sources stages this problem
  std::vector<int>& partner = out.next_partner;  // kept: no allocation in steady state
  if (const int bad = scan_contacts(p, bodies, threads, out.dynamic, partner); bad >= 0)
    return "contact " + std::to_string(bad) + "'s normal row has bounds other than [0, inf)";
  const double t0 = coloring_s != nullptr ? thread_cpu_s() : 0.0;
  const ContactColoring& col =
      ordered != nullptr ? ordered->color(cons, out.dynamic, partner) : colorer.color(cons, out.dynamic, threads);
  if (coloring_s != nullptr) *coloring_s += thread_cpu_s() - t0;
  if (col.repeated && col.generation == out.generation && partner == out.partner &&
      out.numbering.bodies == bodies) {
    // The colours and pairs of the layout in `out` (same contacts, same order, and a numbering of
    // as many bodies): order, ranges and sizes stand; the batches are refilled from this
    // problem's J, b and λ⁰.
    assign_grown(out.failed, out.batches.size() + out.pairs.size(), -1);
    return {};
  }
  out.generation = col.generation;
  out.partner.swap(partner);
  const int* by_key = number(cons, bodies, locality, threads, out);
  // Lead contacts (single contacts and first points of a pair) per slot: 2·colour for singles,
  // 2·colour + 1 for pairs (a pair takes its first point's colour: its second point has the same
  // bodies), overflow last; a counting sort keeping the key order (contact order without
  // locality) inside a slot. With threads:
  // each thread counts and places one contiguous block of contacts, at offsets that put the
  // blocks of a slot in block order: the stable order, whatever the thread count.
  const int nc = cons.size(), ncol = col.colors;
  const int slots = 2 * (ncol + 1);
  const int* colour_of = col.color.data();
  const int* part_of = out.partner.data();
  auto slot_of = [&](int c) {
    const int colour = colour_of[c] == ContactColoring::kOverflow ? ncol : colour_of[c];
    return 2 * colour + (part_of[c] >= 0 ? 1 : 0);
  };
  const int parts = std::max(1, std::min(threads, nc / 4096));
  std::vector<int>& count = out.count;  // count[part·slots + slot]
  assign_grown(count, static_cast<size_t>(parts) * slots, 0);
  std::vector<int>& start = out.start;
  assign_grown(start, static_cast<size_t>(slots) + 1, 0);
  out.order.resize(static_cast<size_t>(nc));
  assign_grown(out.batch_of, static_cast<size_t>(slots) + 1, 0);
  // The sort on the calling thread's team: counts by part, their prefix sums, the scatter.
  auto range = [&](int part, int& lo, int& hi) {
    lo = static_cast<int>(part_begin(nc, parts, part));
    hi = static_cast<int>(part_begin(nc, parts, part + 1));
  };
  WorkTeam& team = calling_thread_team();
  team.for_parts(threads, parts, [&](int part) {
    int lo = 0, hi = 0;
    range(part, lo, hi);
    int* mine = count.data() + static_cast<size_t>(part) * slots;
    for (int i = lo; i < hi; ++i)
      if (const int c = by_key != nullptr ? by_key[i] : i; part_of[c] != -2) ++mine[slot_of(c)];
  });
  // count[part·slots + k] ← the first position of part's contacts of slot k.
  int at = 0;
  for (int k = 0; k < slots; ++k) {
    start[static_cast<size_t>(k)] = at;
    for (int q = 0; q < parts; ++q) {
      const int n = count[static_cast<size_t>(q) * slots + k];
      count[static_cast<size_t>(q) * slots + k] = at;
      at += n;
    }
  }
  start[static_cast<size_t>(slots)] = at;
  team.for_parts(threads, parts, [&](int part) {
    int lo = 0, hi = 0;
    range(part, lo, hi);
    int* mine = count.data() + static_cast<size_t>(part) * slots;
    for (int i = lo; i < hi; ++i)
      if (const int c = by_key != nullptr ? by_key[i] : i; part_of[c] != -2)
        out.order[static_cast<size_t>(mine[slot_of(c)]++)] = c;
  });
  // The overflow set is swept one contact after the other: in contact order, whatever the key.
  if (by_key != nullptr)
    for (int k = slots - 2; k < slots; ++k)
      std::sort(out.order.begin() + start[static_cast<size_t>(k)], out.order.begin() + start[static_cast<size_t>(k) + 1]);
  out.order.resize(static_cast<size_t>(start[static_cast<size_t>(slots)]));
  out.ranges.clear();
  out.slot_of_batch.clear();
  out.slot_of_pair.clear();
  int nb = 0, np = 0;
  for (int k = 0; k < slots; ++k) {
    const bool pairs = (k & 1) != 0, overflow = k / 2 == ncol;
    const int n = start[static_cast<size_t>(k) + 1] - start[static_cast<size_t>(k)];
    const int count_k = overflow ? n : (n + W - 1) / W;
    int& b = pairs ? np : nb;
    out.batch_of[static_cast<size_t>(k)] = b;
    if (count_k > 0) out.ranges.push_back({b, b + count_k, overflow, pairs});
    std::vector<int>& batch_slots = pairs ? out.slot_of_pair : out.slot_of_batch;
    batch_slots.insert(batch_slots.end(), count_k, k);
    b += count_k;
  }
  out.batches.resize(static_cast<size_t>(nb));  // reused storage: every lane is written by the fill
  out.pairs.resize(static_cast<size_t>(np));
  out.pair_base = 2 * W * nb;
  out.row_of.resize(static_cast<size_t>(nb) * 2 * W + static_cast<size_t>(np) * 4 * W);
  out.diag.resize(out.row_of.size());
  assign_grown(out.failed, static_cast<size_t>(nb + np), -1);
  return {};
}

void fill_batch(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out, int bi, double* lp,
                double* other, Batch* into) {
  const int zero = out.body_entries;
  Batch& B = into != nullptr ? *into : out.batches[static_cast<size_t>(bi)];
  int* row_of = out.row_of.data() + static_cast<size_t>(bi) * 2 * W;
  const int k = out.slot_of_batch[static_cast<size_t>(bi)];
  int s0 = 0, lanes = 0;
  lanes_of(out, k, bi - out.batch_of[static_cast<size_t>(k)], s0, lanes);
  double diag_n[W], diag_t[W];  // 1 for padding lanes and rows that failed to pack
  int& failed = out.failed[static_cast<size_t>(bi)];
  bool ok_n = true, ok_t = true;
  const RowSet rs{B.jn, B.mjn, B.jt, B.mjt, B.bn, B.bt, B.mu};
  const bool staged = lanes > 0 && pack_batch_staged(p, out, s0, lanes, B, row_of, diag_n, diag_t, ok_n, ok_t);
  if (staged || (lanes > 0 && pack_batch_simd(p, out, s0, lanes, B, row_of, diag_n, diag_t, ok_n, ok_t))) {
    if (lanes < W) {  // padding as below: zero rows (j = 0·(1/1)), A_ii = 1
      pad_rows(rs, lanes, row_of, row_of + W);
      pad_bodies(lanes, zero, B.la, B.lb, B.ka, B.kb);
      std::fill(diag_n + lanes, diag_n + W, 1.0);
      std::fill(diag_t + lanes, diag_t + W, 1.0);
    }
  } else {
    std::fill(diag_n, diag_n + W, 1.0);
    std::fill(diag_t, diag_t + W, 1.0);
    for (int lane = 0; lane < lanes; ++lane) {
      const int c = out.order[static_cast<size_t>(s0 + lane)];
      if (!pack_contact(p, out, zero, c, rs, B.la, B.lb, B.ka, B.kb, lane, row_of, row_of + W, diag_n,
                        diag_t) &&
          failed < 0)
        failed = c;
    }
    pad_rows(rs, lanes, row_of, row_of + W);
    pad_bodies(lanes, zero, B.la, B.lb, B.ka, B.kb);
    ok_n = scale_rows(B.jn, B.bn, diag_n);
    ok_t = scale_rows(B.jt, B.bt, diag_t);
  }
  if ((!ok_n || !ok_t) && failed < 0) name_singular(out, s0, lanes, diag_n, diag_t, failed);
  B.count = lanes;
  const size_t s0p = static_cast<size_t>(bi) * 2 * W;
  std::copy(diag_n, diag_n + W, out.diag.data() + s0p);
  std::copy(diag_t, diag_t + W, out.diag.data() + s0p + W);
  if (staged) return staged_lambda(out, s0, lanes, lp + s0p, other + s0p);
  for (int s = 0; s < 2 * W; ++s) lp[s0p + s] = other[s0p + s] = row_of[s] >= 0 ? lambda[row_of[s]] : 0.0;
}

void fill_pair(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out, int pi, double* lp, double* other) {
  const int zero = out.body_entries;
  PairBatch& P = out.pairs[static_cast<size_t>(pi)];
  const size_t base = static_cast<size_t>(out.pair_base) + static_cast<size_t>(pi) * 4 * W;
  int* row_of = out.row_of.data() + base;
  const int k = out.slot_of_pair[static_cast<size_t>(pi)];
  int s0 = 0, lanes = 0;
  lanes_of(out, k, pi - out.batch_of[static_cast<size_t>(k)], s0, lanes);
  double dn0[W], dt0[W], dn1[W], dt1[W];
  int& failed = out.failed[out.batches.size() + static_cast<size_t>(pi)];
  const RowSet r0{P.jn0, P.mjn0, P.jt0, P.mjt0, P.bn0, P.bt0, P.mu0};
  const RowSet r1{P.jn1, P.mjn1, P.jt1, P.mjt1, P.bn1, P.bt1, P.mu1};
  bool ok = true;
  if (lanes > 0 && pack_pair_simd(p, out, s0, lanes, P, row_of, dn0, dt0, dn1, dt1, ok)) {
    if (lanes < W) {  // padding as below: zero rows (j = 0·(1/1)), A_ii = 1
      pad_rows(r0, lanes, row_of, row_of + W);
      pad_rows(r1, lanes, row_of + 2 * W, row_of + 3 * W);
      pad_bodies(lanes, zero, P.la, P.lb, P.ka, P.kb);
      for (double* d : {dn0, dt0, dn1, dt1}) std::fill(d + lanes, d + W, 1.0);
    }
  } else {
    for (double* d : {dn0, dt0, dn1, dt1}) std::fill(d, d + W, 1.0);
    ok = fill_pair_lanes(p, out, s0, lanes, P, row_of, dn0, dt0, dn1, dt1, failed);
  }
  for (int lane = lanes; lane < W; ++lane) P.c01[lane] = P.c10[lane] = P.inv_det[lane] = P.block[lane] = 0.0;
  if (!ok && failed < 0) {
    name_singular(out, s0, lanes, dn0, dt0, failed);
    name_singular(out, s0, lanes, dn1, dt1, failed);
  }
  P.count = lanes;
  double* diag = out.diag.data() + base;
  for (const double* d : {dn0, dt0, dn1, dt1}) diag = std::copy(d, d + W, diag);
  for (int s = 0; s < 4 * W; ++s) lp[base + s] = other[base + s] = row_of[s] >= 0 ? lambda[row_of[s]] : 0.0;
}

std::string first_failure(const Prepared& out) {
  for (const int c : out.failed)
    if (c >= 0) return "contact " + std::to_string(c) + "'s rows are singular or act on another body";
  return {};
}

}  // namespace dc::colored
