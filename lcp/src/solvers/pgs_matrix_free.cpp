// "pgs": matrix-free projected Gauss–Seidel on body velocities (the engine default). This
// file is its sweep (MatrixFreeSweep, matrix_free_sweep.hpp, also the sweep of "nncg"); the
// solver is pgs_matrix_free_solver.cpp. A = J M⁻¹ Jᵀ Δt is never formed; the invariant is
//     Δu = M⁻¹ Jᵀ λ Δt   (3 entries per body: Δv_x, Δv_y [m/s], Δω [rad/s]),
// so r_i = A_i·λ + b_i = J_i·Δu + b_i and a row update λ_i += δ restores it with
// Δu += (M⁻¹ J_iᵀ Δt) δ. J_i, b_i are pre-scaled by 1/A_ii in the prepare stage. Kernels are
// chosen per run of rows from LcpProblem::constraints, never from J's sparsity; they perform
// the row-by-row operations in the same order (bit-equal iterates up to the sign of zero, so
// pgs-assembled's to round-off), except two-point manifold blocks (a different Gauss–Seidel
// step, same fixed point). θ_k and the non-finite flag are accumulated off the dependency
// chain; Δu is checked with allFinite after each sweep (an overflowed velocity spoils later
// residuals while λ stays clamped). Kernel design and cost model: docs/lcp.md "The `pgs` kernels".
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "solvers/matrix_free_sweep.hpp"
#include "solvers/pgs_manifold_block.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers {
namespace {

/// One row of J packed on its (at most) two bodies, before it is sorted into a kernel.
struct PackedRow {
  std::array<double, 6> j{};   // J_i / A_ii on (body a: v_x, v_y, ω, body b: v_x, v_y, ω)
  std::array<double, 6> mj{};  // M⁻¹ J_iᵀ Δt on the same 6 entries [(m/s)/N]
  std::array<double, 6> raw{}; // J_i unscaled (manifold detection and A_01)
  double diag = 0.0;           // A_ii [m/(N·s)]
  double b = 0.0;              // b_i / A_ii [N]
  bool singular = false;       // A_ii ≤ 0: j and b are unscaled, see singular_row_update
  int a = -1, bb = -1;         // offsets (3·body) of the two bodies, −1 if absent
};

/// General row: any bounds (fixed or friction-coupled), singular rows.
struct GeneralRow {
  std::array<double, 6> j, mj;
  double b;
  double lo_fixed, hi_fixed;  // fixed bounds (0, 0 for friction rows)
  double mu;                  // μ for friction rows, 0 otherwise
  int la, lb;                 // Δu offsets the row reads (lb: zero body when absent)
  int sa, sb;                 // Δu offsets the row writes (sb: sink body when absent)
  int row, coupled;           // its row; normal row of a friction row, the row itself otherwise
  bool singular;
};

/// Normal row with bounds [0, ∞), not singular.
struct NormalRow {
  std::array<double, 6> j, mj;
  double b;
  int la, lb, sa, sb;
};

/// Contact with friction: normal row (bounds [0, ∞)) and its tangent row right after it,
/// both on the same bodies, both non-singular.
struct ContactBlock {
  std::array<double, 6> jn, mjn, jt, mjt;
  double bn, bt, mu;
  int la, lb, sa, sb;
};

enum class Kind { General, Normal, Contact, ManifoldFriction, ManifoldFrictionless };

/// A run of consecutive rows [row, row + rows) handled by one kernel; `first` indexes the
/// kernel's array.
struct Segment {
  Kind kind;
  int row, rows, first, count;
};


}  // namespace

struct MatrixFreeRows {
  std::vector<GeneralRow> general;
  std::vector<NormalRow> normal;
  std::vector<ContactBlock> contact;
  std::vector<ManifoldBlock> manifold;  // both kinds (pgs_manifold_block.hpp)
  std::vector<Segment> segments;
  std::vector<int> singular;
  int body_entries = 0;  // 3·bodies; the zero body follows at body_entries, the sink after it
};

namespace {

/// Δu offsets of the bodies a contact's rows act on, in slot order: the lower body index
/// first (the order of the row's entries in J, so the row sums run in the same order as for a
/// row read from J alone), −1 for an absent body (wall).
void contact_slots(const ContactConstraint& k, int& a, int& bb) {
  const int first = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
  const int second = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
  a = 3 * first;
  bb = second < 0 ? -1 : 3 * second;
}

/// For a problem without constraint structure: the Δu offsets of the (at most two) bodies row
/// i of J touches, lowest first. Returns false when it touches more than two.
bool row_bodies(const LcpProblem& p, int i, int& a, int& bb) {
  a = bb = -1;
  for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) {
    const int body_off = 3 * (static_cast<int>(it.col()) / 3);
    if (a < 0 || a == body_off) {
      a = body_off;
    } else if (bb < 0 || bb == body_off) {
      bb = body_off;
    } else {
      return false;
    }
  }
  return true;
}

/// Packs row i of J on the bodies at Δu offsets a (slots 0–2) and bb (slots 3–5; −1 absent).
/// Returns false when the row has an entry on another body.
bool pack_row(const LcpProblem& p, int i, int a, int bb, PackedRow& r) {
  r.a = a;
  r.bb = bb;
  for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) {
    const int col = static_cast<int>(it.col());
    const int body_off = 3 * (col / 3), comp = col % 3;
    int slot;
    if (body_off == r.a) {
      slot = comp;
    } else if (r.bb >= 0 && body_off == r.bb) {
      slot = 3 + comp;
    } else {
      return false;
    }
    r.j[static_cast<size_t>(slot)] += it.value();
  }
  double diag = 0.0;  // A_ii = Σ_s J_is (M⁻¹ J_iᵀ Δt)_s, summed in slot order
  for (int s = 0; s < 6; ++s) {
    const int off = s < 3 ? r.a : r.bb;
    if (off < 0) continue;
    const double im = p.inv_mass[off + s % 3];
    r.mj[static_cast<size_t>(s)] = r.j[static_cast<size_t>(s)] * im * p.dt;
    diag += r.j[static_cast<size_t>(s)] * r.mj[static_cast<size_t>(s)];
  }
  r.raw = r.j;
  r.diag = diag;
  const double inv = 1.0 / diag;
  r.singular = !(diag > 0 && std::isfinite(inv));
  const double scale = r.singular ? 1.0 : inv;
  for (double& v : r.j) v *= scale;
  r.b = p.b[i] * scale;
  return true;
}

/// Normal row with the fixed bounds [0, ∞) (standard complementarity).
bool is_plain_normal(const LcpProblem& p, int i) {
  return !p.is_friction_row(i) && p.lo[i] == 0.0 && p.hi[i] == std::numeric_limits<double>::infinity();
}

/// Builds the segments from the problem's contact constraints: with `block_manifolds`, two
/// contacts of a two-point manifold become a ManifoldBlock (see try_manifold below); a
/// contact whose tangent row follows its normal row becomes a ContactBlock, a frictionless
/// contact a NormalRow, and every other row (singular, other bounds, tangent rows elsewhere)
/// a GeneralRow. A problem without constraint structure (built by hand with J) runs every row
/// in the general kernel. Returns an error message when a row of J acts on a body that is not
/// one of its contact's, or (without constraints) on more than two bodies.
std::string prepare(const LcpProblem& p, bool block_manifolds, MatrixFreeRows& out) {
  const int n = p.rows();
  const int bodies = static_cast<int>(p.J.cols() / 3) + (p.J.cols() % 3 != 0 ? 1 : 0);
  out.body_entries = 3 * bodies;
  const int zero = out.body_entries, sink = out.body_entries + 3;
  auto load_a = [&](const PackedRow& r) { return r.a < 0 ? zero : r.a; };
  auto load_b = [&](const PackedRow& r) { return r.bb < 0 ? zero : r.bb; };
  auto store_a = [&](const PackedRow& r) { return r.a < 0 ? sink : r.a; };
  auto store_b = [&](const PackedRow& r) { return r.bb < 0 ? sink : r.bb; };
  auto add = [&](Kind kind, int row, int rows, int index) {
    if (!out.segments.empty() && out.segments.back().kind == kind) {
      out.segments.back().rows += rows;
      ++out.segments.back().count;
    } else {
      out.segments.push_back({kind, row, rows, index, 1});
    }
  };
  const ContactConstraints& cons = p.constraints;
  std::vector<int> owner(static_cast<size_t>(n), -1);  // contact of each row (validated: one)
  for (int c = 0; c < cons.size(); ++c) {
    owner[static_cast<size_t>(cons[c].normal_row)] = c;
    if (cons[c].has_friction()) owner[static_cast<size_t>(cons[c].tangent_row)] = c;
  }
  auto pack = [&](int i, PackedRow& r) -> std::string {
    const int c = owner[static_cast<size_t>(i)];
    int a = -1, bb = -1;
    if (c >= 0) {
      contact_slots(cons[c], a, bb);
    } else if (!row_bodies(p, i, a, bb)) {
      return "row " + std::to_string(i) + " of J touches more than two bodies";
    }
    if (!pack_row(p, i, a, bb, r))
      return "row " + std::to_string(i) + " of J acts on a body other than the two bodies of its contact " +
             std::to_string(c);
    return {};
  };
  // A two-point manifold starting at normal row i (contact c, packed as n0): the next
  // contact's normal row follows right after c's rows (i + 2 with friction, i + 1 without) and
  // that contact has the same body_a and body_b, another feature, a tangent row exactly when c
  // has one (right after its normal row), the same normal (bit-equal linear parts of J: the
  // narrow phase gives both points of a manifold the reference face's normal, so contacts on
  // two different walls or static bodies, which also have body_a = −1, are not paired), a
  // plain [0, ∞) non-singular normal row, non-singular tangent rows, and the 2 × 2 normal
  // block passes the conditioning test. Sets `used` to the rows taken (0: not a manifold).
  auto try_manifold = [&](int i, int c, const PackedRow& n0, int& used) -> std::string {
    used = 0;
    const ContactConstraint& k0 = cons[c];
    const bool fr = k0.has_friction();
    if (fr && k0.tangent_row != i + 1) return {};
    const int i1 = fr ? i + 2 : i + 1;
    if (i1 >= n) return {};
    const int c1 = owner[static_cast<size_t>(i1)];
    if (c1 < 0) return {};
    const ContactConstraint& k1 = cons[c1];
    if (k1.normal_row != i1 || k1.body_a != k0.body_a || k1.body_b != k0.body_b || k1.feature == k0.feature ||
        k1.has_friction() != fr || (fr && k1.tangent_row != i1 + 1) || !is_plain_normal(p, i1))
      return {};
    PackedRow n1, t0, t1;
    if (std::string err = pack(i1, n1); !err.empty()) return err;
    if (n1.singular) return {};
    for (int s : {0, 1, 3, 4})
      if (n0.raw[static_cast<size_t>(s)] != n1.raw[static_cast<size_t>(s)]) return {};
    double a01 = 0.0;  // A_01 = J_0 M⁻¹ J_1ᵀ Δt, summed in slot order
    for (size_t s = 0; s < 6; ++s) a01 += n0.raw[s] * n1.mj[s];
    if (!manifold_block_conditioned(n0.diag, n1.diag, a01)) return {};
    if (fr) {
      if (std::string err = pack(i + 1, t0); !err.empty()) return err;
      if (std::string err = pack(i1 + 1, t1); !err.empty()) return err;
      if (t0.singular || t1.singular) return {};
    }
    add(fr ? Kind::ManifoldFriction : Kind::ManifoldFrictionless, i, fr ? 4 : 2,
        static_cast<int>(out.manifold.size()));
    ManifoldBlock& mb = out.manifold.emplace_back();
    mb.jn0 = n0.j;
    mb.mjn0 = n0.mj;
    mb.jn1 = n1.j;
    mb.mjn1 = n1.mj;
    mb.jt0 = t0.j;
    mb.mjt0 = t0.mj;
    mb.jt1 = t1.j;
    mb.mjt1 = t1.mj;
    mb.bn0 = n0.b;
    mb.bn1 = n1.b;
    mb.bt0 = t0.b;
    mb.bt1 = t1.b;
    mb.mu0 = k0.mu;
    mb.mu1 = k1.mu;
    mb.c01 = a01 / n0.diag;
    mb.c10 = a01 / n1.diag;
    mb.inv_det = 1.0 / (1.0 - mb.c01 * mb.c10);
    mb.la = load_a(n0);
    mb.lb = load_b(n0);
    mb.sa = store_a(n0);
    mb.sb = store_b(n0);
    used = fr ? 4 : 2;
    return {};
  };
  out.contact.reserve(static_cast<size_t>(cons.size()));
  for (int i = 0; i < n;) {
    PackedRow r;
    if (std::string err = pack(i, r); !err.empty()) return err;
    if (r.singular) out.singular.push_back(i);
    const int c = owner[static_cast<size_t>(i)];
    const bool plain_normal = c >= 0 && cons[c].normal_row == i && !r.singular && is_plain_normal(p, i);
    if (block_manifolds && plain_normal) {
      int used = 0;
      if (std::string err = try_manifold(i, c, r, used); !err.empty()) return err;
      if (used > 0) {
        i += used;
        continue;
      }
    }
    if (plain_normal && cons[c].tangent_row == i + 1) {
      PackedRow t;
      if (std::string err = pack(i + 1, t); !err.empty()) return err;
      if (!t.singular) {
        add(Kind::Contact, i, 2, static_cast<int>(out.contact.size()));
        // Filled in place: a braced temporary would be built and then copied.
        ContactBlock& cb = out.contact.emplace_back();
        cb.jn = r.j;
        cb.mjn = r.mj;
        cb.jt = t.j;
        cb.mjt = t.mj;
        cb.bn = r.b;
        cb.bt = t.b;
        cb.mu = cons[c].mu;
        cb.la = load_a(r);
        cb.lb = load_b(r);
        cb.sa = store_a(r);
        cb.sb = store_b(r);
        i += 2;
        continue;
      }
    }
    if (plain_normal) {
      add(Kind::Normal, i, 1, static_cast<int>(out.normal.size()));
      out.normal.push_back({r.j, r.mj, r.b, load_a(r), load_b(r), store_a(r), store_b(r)});
    } else {
      const bool fr = p.is_friction_row(i);
      add(Kind::General, i, 1, static_cast<int>(out.general.size()));
      out.general.push_back({r.j, r.mj, r.b, fr ? 0.0 : p.lo[i], fr ? 0.0 : p.hi[i], fr ? p.mu[i] : 0.0,
                             load_a(r), load_b(r), store_a(r), store_b(r), i,
                             fr ? p.normal_row[static_cast<size_t>(i)] : i, r.singular});
    }
    ++i;
  }
  return {};
}

// The multiply-adds on the chain are explicit std::fma (DC_PGS_FMA_CLONES and SweepAcc:
// pgs_manifold_block.hpp).

DC_PGS_FMA_CLONES void sweep_general(const GeneralRow* __restrict row, int count, double* __restrict lam,
                   double* __restrict u, SweepAcc& acc) {
  double theta = acc.theta;
  bool bad = acc.bad;
  for (int k = 0; k < count; ++k, ++row) {
    const double* ua = u + row->la;
    const double* ub = u + row->lb;
    const double a0 = ua[0], a1 = ua[1], a2 = ua[2], b0 = ub[0], b1 = ub[1], b2 = ub[2];
    // Pairwise (tree) sum: a left-to-right sum of 7 terms would put 6 serial adds on the
    // dependency chain.
    const double s0 = std::fma(row->j[0], a0, row->j[1] * a1);
    const double s1 = std::fma(row->j[2], a2, row->j[3] * b0);
    const double s2 = std::fma(row->j[4], b1, row->j[5] * b2);
    const double res = (row->b + s0) + (s1 + s2);
    const int i = row->row;
    const double old = lam[i];
    const double t = row->mu * std::max(0.0, lam[row->coupled]);
    const double lo = row->lo_fixed - t, hi = row->hi_fixed + t;
    double x = !row->singular ? old - res : singular_row_update(old, res, lo, hi);
    x = std::min(std::max(x, lo), hi);  // NaN propagates (x is the first argument)
    const double d = x - old;
    bad |= !std::isfinite(x);
    lam[i] = x;
    double* sa = u + row->sa;
    double* sb = u + row->sb;
    sa[0] = std::fma(row->mj[0], d, a0);
    sa[1] = std::fma(row->mj[1], d, a1);
    sa[2] = std::fma(row->mj[2], d, a2);
    sb[0] = std::fma(row->mj[3], d, b0);
    sb[1] = std::fma(row->mj[4], d, b1);
    sb[2] = std::fma(row->mj[5], d, b2);
    theta = std::max(theta, std::abs(d));
  }
  acc.theta = theta;
  acc.bad = bad;
}

DC_PGS_FMA_CLONES void sweep_normal(const NormalRow* __restrict row, int count, double* __restrict lam,
                  double* __restrict u, SweepAcc& acc) {
  double theta = acc.theta;
  bool bad = acc.bad;
  for (int k = 0; k < count; ++k, ++row) {
    const double* ua = u + row->la;
    const double* ub = u + row->lb;
    const double a0 = ua[0], a1 = ua[1], a2 = ua[2], b0 = ub[0], b1 = ub[1], b2 = ub[2];
    const double s0 = std::fma(row->j[0], a0, row->j[1] * a1);
    const double s1 = std::fma(row->j[2], a2, row->j[3] * b0);
    const double s2 = std::fma(row->j[4], b1, row->j[5] * b2);
    const double res = (row->b + s0) + (s1 + s2);
    const double old = lam[k];
    // Bounds [0, ∞): min(max(y, 0), ∞) = max(y, 0) (NaN propagates), as a branch.
    const double y = old - res;
    double x;
    if (y < 0.0) {
      x = 0.0;
    } else {
      x = y;
      bad |= !std::isfinite(y);
    }
    const double d = x - old;
    lam[k] = x;
    double* sa = u + row->sa;
    double* sb = u + row->sb;
    sa[0] = std::fma(row->mj[0], d, a0);
    sa[1] = std::fma(row->mj[1], d, a1);
    sa[2] = std::fma(row->mj[2], d, a2);
    sb[0] = std::fma(row->mj[3], d, b0);
    sb[1] = std::fma(row->mj[4], d, b1);
    sb[2] = std::fma(row->mj[5], d, b2);
    theta = std::max(theta, std::abs(d));
  }
  acc.theta = theta;
  acc.bad = bad;
}

// GCC's SLP vectoriser is off here: it packs pairs of the 6 velocity entries into vectors
// and extracts them again with shuffles, which puts extra latency on the chain.
[[gnu::optimize("no-tree-slp-vectorize")]] DC_PGS_FMA_CLONES void sweep_contacts(const ContactBlock* __restrict c,
                                                                int count, double* __restrict lam,
                                                                double* __restrict u, SweepAcc& acc) {
  double theta = acc.theta;
  bool bad = acc.bad;
  for (int k = 0; k < count; ++k, ++c, lam += 2) {
    const double* ua = u + c->la;
    const double* ub = u + c->lb;
    double a0 = ua[0], a1 = ua[1], a2 = ua[2], b0 = ub[0], b1 = ub[1], b2 = ub[2];
    double xn;
    // Normal row: r_n = J_n·Δu + b_n (scaled by 1/A_nn), λ_n ← max(0, λ_n − r_n).
    {
      const double s0 = std::fma(c->jn[0], a0, c->jn[1] * a1);
      const double s1 = std::fma(c->jn[2], a2, c->jn[3] * b0);
      const double s2 = std::fma(c->jn[4], b1, c->jn[5] * b2);
      const double res = (c->bn + s0) + (s1 + s2);
      const double old = lam[0];
      const double y = old - res;
      if (y < 0.0) {  // = std::max(y, 0.0), as a branch: see docs/lcp.md "The `pgs` kernels"
        xn = 0.0;
      } else {
        xn = y;
        bad |= !std::isfinite(y);
      }
      const double d = xn - old;
      lam[0] = xn;
      a0 = std::fma(c->mjn[0], d, a0);
      a1 = std::fma(c->mjn[1], d, a1);
      a2 = std::fma(c->mjn[2], d, a2);
      b0 = std::fma(c->mjn[3], d, b0);
      b1 = std::fma(c->mjn[4], d, b1);
      b2 = std::fma(c->mjn[5], d, b2);
      theta = std::max(theta, std::abs(d));
    }
    // Tangent row on the updated velocities, bounds ±μ max(0, λ_n) with the fresh λ_n.
    {
      const double s0 = std::fma(c->jt[0], a0, c->jt[1] * a1);
      const double s1 = std::fma(c->jt[2], a2, c->jt[3] * b0);
      const double s2 = std::fma(c->jt[4], b1, c->jt[5] * b2);
      const double res = (c->bt + s0) + (s1 + s2);
      const double old = lam[1];
      const double t = c->mu * std::max(0.0, xn);
      const double y = old - res;
      const double x = friction_clamp(y, t, bad);  // a branch on t (docs/lcp.md "The `pgs` kernels")
      const double d = x - old;
      lam[1] = x;
      a0 = std::fma(c->mjt[0], d, a0);
      a1 = std::fma(c->mjt[1], d, a1);
      a2 = std::fma(c->mjt[2], d, a2);
      b0 = std::fma(c->mjt[3], d, b0);
      b1 = std::fma(c->mjt[4], d, b1);
      b2 = std::fma(c->mjt[5], d, b2);
      theta = std::max(theta, std::abs(d));
    }
    double* sa = u + c->sa;
    double* sb = u + c->sb;
    sa[0] = a0;
    sa[1] = a1;
    sa[2] = a2;
    sb[0] = b0;
    sb[1] = b1;
    sb[2] = b2;
  }
  acc.theta = theta;
  acc.bad = bad;
}

}  // namespace

MatrixFreeSweep::MatrixFreeSweep() : rows_(std::make_unique<MatrixFreeRows>()) {}
MatrixFreeSweep::~MatrixFreeSweep() = default;

std::string MatrixFreeSweep::prepare(const LcpProblem& p, bool block_manifolds) {
  *rows_ = MatrixFreeRows{};
  return solvers::prepare(p, block_manifolds, *rows_);
}

int MatrixFreeSweep::body_entries() const { return rows_->body_entries; }

const std::vector<int>& MatrixFreeSweep::singular_rows() const { return rows_->singular; }

std::vector<double> MatrixFreeSweep::velocity_change(const LcpProblem& p, const Eigen::VectorXd& lambda) const {
  std::vector<double> du(static_cast<size_t>(rows_->body_entries + 6), 0.0);
  const Eigen::VectorXd jt = p.J.transpose() * lambda;
  for (int c = 0; c < jt.size(); ++c) du[static_cast<size_t>(c)] = p.inv_mass[c] * jt[c] * p.dt;
  return du;
}

double MatrixFreeSweep::sweep(double* lam, double* u, bool& nonfinite) const {
  const MatrixFreeRows& prep = *rows_;
  SweepAcc acc;
  for (const Segment& s : prep.segments) {
    switch (s.kind) {
      case Kind::Contact:
        sweep_contacts(prep.contact.data() + s.first, s.count, lam + s.row, u, acc);
        break;
      case Kind::Normal:
        sweep_normal(prep.normal.data() + s.first, s.count, lam + s.row, u, acc);
        break;
      case Kind::General:
        sweep_general(prep.general.data() + s.first, s.count, lam, u, acc);
        break;
      case Kind::ManifoldFriction:
        sweep_manifolds_friction(prep.manifold.data() + s.first, s.count, lam + s.row, u, acc);
        break;
      case Kind::ManifoldFrictionless:
        sweep_manifolds_frictionless(prep.manifold.data() + s.first, s.count, lam + s.row, u, acc);
        break;
    }
  }
  if (!std::isfinite(acc.theta) ||
      !Eigen::Map<const Eigen::VectorXd>(u, prep.body_entries).allFinite())
    acc.bad = true;
  nonfinite = nonfinite || acc.bad;
  return acc.theta;
}

}  // namespace dc::solvers
