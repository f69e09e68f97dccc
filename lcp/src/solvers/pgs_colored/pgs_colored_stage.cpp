// pgs-colored's staging of the packing's sources (pgs_colored_layout.hpp, stage_sources): one
// pass over the contacts in their own order, so J, b and λ⁰ are read as they lie in memory (on
// the team: each member a block of the contacts).
#include <algorithm>

#include "dc/core/work_team.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/pgs_colored_pack_simd.hpp"

namespace dc::colored {

void stage_sources(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Prepared& out, int from,
                   int threads) {
  const size_t positions = out.order.size();
  out.staged_now = false;
  if (positions < static_cast<size_t>(std::max(0, from)) || !simd_pack_available()) return;
  out.staged.resize(positions);
  out.usable.resize(positions);
  const ContactConstraint* cons = p.constraints.contacts().data();
  const int nc = p.constraints.size();
  out.position.resize(static_cast<size_t>(nc));
  // Blocks of the positions, then of the contacts: a few per member, so that one that comes free
  // first takes over part of a late one's.
  const int parts = threads > 1 ? 4 * threads : 1;
  auto block = [parts](long n, int part, int& lo, int& hi) {
    lo = static_cast<int>(part_begin(n, parts, part));
    hi = static_cast<int>(part_begin(n, parts, part + 1));
  };
  WorkTeam& team = calling_thread_team();
  team.for_parts(threads, parts, [&](int part) {
    int lo = 0, hi = 0;
    block(static_cast<long>(positions), part, lo, hi);
    for (int q = lo; q < hi; ++q) out.position[static_cast<size_t>(out.order[static_cast<size_t>(q)])] = q;
  });
  const int* outer = p.J.outerIndexPtr();
  const int* inner = p.J.innerIndexPtr();
  const int* nnz = p.J.isCompressed() ? nullptr : p.J.innerNonZeroPtr();
  const double* value = p.J.valuePtr();
  // The usual storage (pack_rows_simd's): the columns a, a+1, a+2 (, bb, bb+1, bb+2) once each.
  auto usual = [&](int i, int a, int bb) {
    const int q0 = outer[i], n = nnz != nullptr ? nnz[i] : outer[i + 1] - q0;
    const int* col = inner + q0;
    return n == (bb < 0 ? 3 : 6) && col[0] == a && col[1] == a + 1 && col[2] == a + 2 &&
           (bb < 0 || (col[3] == bb && col[4] == bb + 1 && col[5] == bb + 2));
  };
  auto stage = [&](int c) {
    if (out.partner[static_cast<size_t>(c)] != -1) return;  // pairs are packed from J
    const ContactConstraint& k = cons[c];
    const size_t q = static_cast<size_t>(out.position[static_cast<size_t>(c)]);
    const int first = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
    const int second = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
    const int a = 3 * first, bb = second < 0 ? -1 : 3 * second;
    const bool ok = k.has_friction() && usual(k.normal_row, a, bb) && usual(k.tangent_row, a, bb);
    out.usable[q] = ok ? 1 : 0;
    if (!ok) return;
    StagedRows& s = out.staged[q];
    const int n = bb < 0 ? 3 : 6;
    const double* vn = value + outer[k.normal_row];
    const double* vt = value + outer[k.tangent_row];
    for (int e = 0; e < 6; ++e) {
      s.vn[e] = e < n ? vn[e] : 0.0;
      s.vt[e] = e < n ? vt[e] : 0.0;
    }
    s.bn = p.b[k.normal_row];
    s.bt = p.b[k.tangent_row];
    s.ln = lambda[k.normal_row];
    s.lt = lambda[k.tangent_row];
    s.mu = k.mu;
    s.rn = k.normal_row;
    s.rt = k.tangent_row;
    s.a = a;
    s.bb = bb;
  };
  team.for_parts(threads, parts, [&](int part) {
    int lo = 0, hi = 0;
    block(nc, part, lo, hi);
    for (int c = lo; c < hi; ++c) stage(c);
  });
  out.staged_now = true;
}

bool pack_batch_staged(const LcpProblem& p, const Prepared& out, int s0, int lanes, Batch& B, int* row_of,
                       double* diag_n, double* diag_t, bool& ok_n, bool& ok_t) {
  if (!out.staged_now) return false;
  constexpr int kRecord = sizeof(StagedRows) / sizeof(double);
  int on[W], ot[W], a[W], bb[W];
  double bn[W], bt[W];
  const StagedRows* st = out.staged.data();
  for (int lane = 0; lane < W; ++lane) {
    const int q = s0 + (lane < lanes ? lane : 0);
    if (out.usable[static_cast<size_t>(q)] == 0) return false;
    a[lane] = st[q].a;
    bb[lane] = st[q].bb;
    on[lane] = q * kRecord;
    ot[lane] = q * kRecord + 6;
    bn[lane] = st[q].bn;
    bt[lane] = st[q].bt;
  }
  const double* base = st[0].vn;
  const double* im = p.inv_mass.data();
  unsigned singular_n = 0, singular_t = 0;
  if (!pack_rows_staged(base, on, bn, a, bb, im, p.dt, B.jn, B.mjn, B.bn, diag_n, singular_n) ||
      !pack_rows_staged(base, ot, bt, a, bb, im, p.dt, B.jt, B.mjt, B.bt, diag_t, singular_t))
    return false;
  for (int lane = 0; lane < lanes; ++lane) {
    const StagedRows& r = st[s0 + lane];
    put_lane(out, B, row_of, lane, a[lane] / 3, bb[lane] < 0 ? -1 : bb[lane] / 3, r.mu, r.rn, r.rt);
  }
  const unsigned used = (1u << lanes) - 1u;
  ok_n = (singular_n & used) == 0;
  ok_t = (singular_t & used) == 0;
  return true;
}

void staged_lambda(const Prepared& out, int s0, int lanes, double* lp, double* other) {
  const StagedRows* st = out.staged.data() + s0;
  for (int lane = 0; lane < W; ++lane) {
    lp[lane] = other[lane] = lane < lanes ? st[lane].ln : 0.0;
    lp[W + lane] = other[W + lane] = lane < lanes ? st[lane].lt : 0.0;
  }
}

}  // namespace dc::colored
