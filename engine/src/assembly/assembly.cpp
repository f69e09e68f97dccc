#include "assembly/assembly.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "dc/core/error.hpp"

#include "world/parts/step_parts.hpp"

namespace dc {

namespace {

/// dst = v, written only when dst does not hold v's bits already. The bounds, μ and normal
/// rows of a contact's rows depend on its row number alone when every contact has friction, so
/// from step to step they are mostly the values already there: a line left clean needs no
/// write-back to the next cache level (beyond L2 that traffic bounds the assembly's pace).
template <class T>
[[gnu::always_inline]] inline void keep_or_put(T& dst, T v) {
  if constexpr (sizeof(T) == 8) {
    if (std::bit_cast<std::uint64_t>(dst) != std::bit_cast<std::uint64_t>(v)) dst = v;
  } else {
    if (dst != v) dst = v;
  }
}

/// The rows of contact c (its constraint kc): J's entries at the row starts already in J, b,
/// the bounds, μ and the normal row of its tangent row.
void fill_rows(const BodyState& s, const Contact& ct, const ContactConstraint& kc, const WorldDef& def,
               LcpProblem& out) {
  const double dt = def.time.dt;
  const ContactSection& cs = def.contact;
  const Vec2 g = def.world.gravity;
  const int* const outer = out.J.outerIndexPtr();
  int* const inner = out.J.innerIndexPtr();
  double* const value = out.J.valuePtr();
  const Vec2 n = ct.normal, t = perp(n);
  const int rn = kc.normal_row, rt = kc.tangent_row;
  const bool friction = kc.has_friction();
  double vn = 0, vt = 0;       // J u       (relative velocity before the step)
  double vn_f = 0, vt_f = 0;   // J Δt M⁻¹ F_ext  (gravity only: Δt·g on linear dofs)
  // Row rn holds entries [outer[rn], outer[rn] + per_row), row rt the next per_row.
  const int per_row = kc.body_a >= 0 ? 6 : 3;  // a static/kinematic body_a has no columns
  const int first_n = outer[rn];
  const int first_t = first_n + per_row;
  auto put = [&](int at, int col, double v) {
    inner[at] = col;
    value[at] = v;
  };
  auto add_body = [&](int body, double sign, int slot) {
    const auto k = static_cast<size_t>(body);
    const Vec2 r = ct.point - s.position[k];
    const double rn_x = cross(r, n), rt_x = cross(r, t);
    put(first_n + slot, 3 * body, sign * n.x);
    put(first_n + slot + 1, 3 * body + 1, sign * n.y);
    put(first_n + slot + 2, 3 * body + 2, sign * rn_x);
    vn += sign * (dot(n, s.velocity[k]) + rn_x * s.omega[k]);
    vn_f += sign * dt * dot(n, g);
    if (friction) {
      put(first_t + slot, 3 * body, sign * t.x);
      put(first_t + slot + 1, 3 * body + 1, sign * t.y);
      put(first_t + slot + 2, 3 * body + 2, sign * rt_x);
      vt += sign * (dot(t, s.velocity[k]) + rt_x * s.omega[k]);
      vt_f += sign * dt * dot(t, g);
    }
  };
  // The sums run body a, then body b (this order fixes the rounding of vn, vt); the columns of
  // the body with the lower index come first in each row.
  if (kc.body_a >= 0) {
    const bool a_first = ct.body_a < ct.body_b;
    add_body(ct.body_a, -1.0, a_first ? 0 : 3);
    add_body(ct.body_b, +1.0, a_first ? 3 : 0);
  } else {
    if (ct.body_a >= 0) {
      // Static / kinematic body_a: no columns, no gravity; its velocity at the point enters b
      // as a moving boundary's (relative velocity J u with the boundary's u).
      const auto k = static_cast<size_t>(ct.body_a);
      const Vec2 r = ct.point - s.position[k];
      vn -= dot(n, s.velocity[k]) + cross(r, n) * s.omega[k];
      vt -= dot(t, s.velocity[k]) + cross(r, t) * s.omega[k];
    }
    add_body(ct.body_b, +1.0, 0);
  }

  // b of the normal row: relative velocity + gravity + stabilisation + restitution.
  double bn = vn + vn_f;
  if (ct.gap > 0) {
    bn += ct.gap / dt;  // speculative: may close at most the open gap this step
  } else {
    bn += cs.baumgarte * std::min(0.0, ct.gap + cs.slop) / dt;
  }
  // Restitution (restitution.hpp): aim at −e·v_a, v_a the stored approach velocity.
  if (cs.restitution > 0 && ct.restitution_due && ct.approach_velocity < -cs.restitution_threshold)
    bn = std::min(bn, vn + vn_f + cs.restitution * ct.approach_velocity);
  constexpr double inf = std::numeric_limits<double>::infinity();
  out.b[rn] = bn;
  keep_or_put(out.lo[rn], 0.0);
  keep_or_put(out.hi[rn], inf);
  keep_or_put(out.mu[rn], 0.0);
  if (friction) {
    out.b[rt] = vt + vt_f;
    keep_or_put(out.lo[rt], -inf);  // effective bounds: ±μ λ_n
    keep_or_put(out.hi[rt], inf);
    keep_or_put(out.mu[rt], kc.mu);
    keep_or_put(out.normal_row[static_cast<size_t>(rt)], rn);
  }
}

/// Contact ct's body_a as its rows see it: a static or kinematic body_a (infinite mass) owns no
/// columns, so its rows are one-body rows, like a wall's (-1).
int row_body_a(const BodyState& s, const Contact& ct) {
  const bool motion_types = !s.shapes.empty();
  return ct.body_a >= 0 && (!motion_types || s.shapes.is_dynamic(static_cast<size_t>(ct.body_a))) ? ct.body_a : -1;
}

/// M⁻¹ of bodies [k0, k1) into out.inv_mass (m⁻¹ for x and y, I⁻¹ for the angle).
void fill_inv_mass(const BodyState& s, int k0, int k1, LcpProblem& out) {
  for (int k = k0; k < k1; ++k) {
    const double m = s.inv_mass[static_cast<size_t>(k)];
    keep_or_put(out.inv_mass[3 * k], m);
    keep_or_put(out.inv_mass[3 * k + 1], m);
    keep_or_put(out.inv_mass[3 * k + 2], s.inv_inertia[static_cast<size_t>(k)]);
  }
}

/// Contacts come sorted by body a, so body a is read in order; body b is anywhere unless the
/// bodies follow space: its fields are fetched kAhead contacts before contact c's rows are
/// filled (a hint, no effect on values), within [.., c_end). Reading contact c + kAhead's
/// body_b for that would wait for its cache line (the list is larger than the caches): the
/// line is fetched a further kAhead contacts ahead.
[[gnu::always_inline]] inline void prefetch_body_b(const BodyState& s, const std::vector<Contact>& contacts, int c,
                                                   int c_end) {
  constexpr int kAhead = 8;
  if (c + 2 * kAhead < c_end) __builtin_prefetch(&contacts[static_cast<size_t>(c + 2 * kAhead)]);
  if (c + kAhead < c_end) {
    const auto b = static_cast<size_t>(contacts[static_cast<size_t>(c + kAhead)].body_b);
    __builtin_prefetch(&s.position[b]);
    __builtin_prefetch(&s.velocity[b]);
    __builtin_prefetch(&s.omega[b]);
  }
}

/// Storage kept beyond a size that grew, as a fraction of it: a pile whose contacts grow step
/// by step reallocates a few times, not at every step.
constexpr double kHeadroom = 0.25;

/// Contact ct's constraint kc and rows, its first row `row` and first J entry `at` (both
/// advanced past them) as add() numbers them; false (nothing written but kc's bodies and μ)
/// when it fails add()'s checks.
bool write_contact(const BodyState& s, const Contact& ct, const WorldDef& def, ContactConstraint& kc, int& row,
                   int& at, LcpProblem& out) {
  kc.body_a = row_body_a(s, ct);
  kc.body_b = ct.body_b;
  kc.mu = friction_of(ct, def.contact);
  if (!ContactConstraints::valid(kc.body_a, kc.body_b, kc.mu)) return false;
  int* const outer = out.J.outerIndexPtr();
  kc.feature = ct.key.feature;
  const int per_row = kc.body_a >= 0 ? 6 : 3;
  kc.normal_row = row++;
  outer[kc.normal_row] = at;
  at += per_row;
  keep_or_put(out.normal_row[static_cast<size_t>(kc.normal_row)], -1);
  kc.tangent_row = -1;
  if (kc.mu > 0) {
    kc.tangent_row = row++;
    outer[kc.tangent_row] = at;
    at += per_row;
  }
  fill_rows(s, ct, kc, def, out);
  return true;
}

/// assemble_lcp on the calling thread in one pass over the contacts: each contact's constraint
/// (rows numbered as ContactConstraints::add numbers them, after its checks), row starts and rows.
void assemble_serial(const BodyState& s, const std::vector<Contact>& contacts, const WorldDef& def,
                     LcpProblem& out) {
  const int nb = static_cast<int>(s.size());
  const int nc = static_cast<int>(contacts.size());
  const ContactSection& cs = def.contact;
  int rows = 0;
  for (const Contact& ct : contacts) rows += friction_of(ct, cs) > 0 ? 2 : 1;
  const std::span<ContactConstraint> con = out.constraints.overwrite(static_cast<size_t>(nc), rows);
  out.dt = def.time.dt;
  out.inv_mass.resize(3 * nb);

  // J in compressed row storage, filled in place (rows come in order and each row's columns
  // in ascending order, so no triplet list, sort or transpose is needed): the normal row
  // and the tangent row of a contact both hold 3 entries per body it acts on (walls have no
  // columns), body columns in ascending body order. Explicit zeros are stored, exactly as
  // setFromTriplets stored them; storage is reused from step to step. At most 6 entries a row
  // are held, the count set to the entries filled at the end.
  out.J.resize_keeping(rows, 3 * nb);
  out.J.data().resize(6 * static_cast<Eigen::Index>(rows), kHeadroom);
  int* const outer = out.J.outerIndexPtr();
  out.b.resize(rows);
  out.lo.resize(rows);
  out.hi.resize(rows);
  out.mu.resize(rows);
  out.normal_row.resize(static_cast<size_t>(rows));  // grows geometrically (filled below)

  fill_inv_mass(s, 0, nb, out);
  int row = 0, at = 0;  // the contact's first row and J entry
  for (int c = 0; c < nc; ++c) {
    prefetch_body_b(s, contacts, c, nc);
    const Contact& ct = contacts[static_cast<size_t>(c)];
    ContactConstraint& kc = con[static_cast<size_t>(c)];
    // add()'s checks; check() throws the one-line error for the contact that fails them.
    if (!write_contact(s, ct, def, kc, row, at, out)) ContactConstraints::check(c, kc.body_a, kc.body_b, kc.mu);
  }
  outer[rows] = at;
  out.J.data().resize(at);
}

/// `out` sized for nc contacts with `rows` rows and `nnz` J entries on nb bodies, J as
/// assemble_serial lays it out (its end set); the constraints to overwrite.
std::span<ContactConstraint> size_problem(int nb, int nc, int rows, int nnz, const WorldDef& def, LcpProblem& out) {
  const std::span<ContactConstraint> con = out.constraints.overwrite(static_cast<size_t>(nc), rows);
  out.dt = def.time.dt;
  out.inv_mass.resize(3 * nb);
  out.J.resize_keeping(rows, 3 * nb);
  out.J.data().resize(nnz, kHeadroom);  // as resizeNonZeros, with room to grow
  out.J.outerIndexPtr()[rows] = nnz;
  out.b.resize(rows);
  out.lo.resize(rows);
  out.hi.resize(rows);
  out.mu.resize(rows);
  out.normal_row.resize(static_cast<size_t>(rows));
  return con;
}

/// A job's tally in assemble_jobs (its rows and J entries, then its first row and entry) and
/// assemble_direct (whether its contacts broke the premises); both: its first contact failing
/// add()'s checks. One cache line each: the jobs of different threads write their own.
struct alignas(64) JobTally {
  int rows = 0, nnz = 0, bad = -1;
  bool broken = false;
};

/// `jobs` fresh tallies in storage kept by the calling thread (the thread of the World whose
/// step assembles), so a threaded assembly allocates nothing once it has held that many jobs.
std::span<JobTally> job_tallies(int jobs) {
  thread_local std::vector<JobTally> kept;
  kept.assign(static_cast<size_t>(jobs), JobTally{});
  return kept;
}

/// assemble_lcp on `threads` threads in `jobs` (> 1) jobs.
void assemble_jobs(const BodyState& s, const std::vector<Contact>& contacts, const WorldDef& def,
                   LcpProblem& out, int threads, int jobs) {
  const int nb = static_cast<int>(s.size());
  const int nc = static_cast<int>(contacts.size());
  const ContactSection& cs = def.contact;
  // Jobs of contacts (and of bodies): a first run counts each job's rows and J entries; the
  // second writes each job's contacts, rows and J entries from its offsets, numbered as add()
  // numbers them, so the problem is the same for every job count. A contact failing add()'s
  // checks is skipped and the first one is thrown after the run.
  JobTally* const count = job_tallies(jobs).data();
  run_parts(threads, jobs, [&](int part) {
    JobTally& k = count[part];
    const int c_end = static_cast<int>(part_begin(nc, jobs, part + 1));
    for (int c = static_cast<int>(part_begin(nc, jobs, part)); c < c_end; ++c) {
      const Contact& ct = contacts[static_cast<size_t>(c)];
      const double mu = friction_of(ct, cs);
      const int a = row_body_a(s, ct);
      const int rows = mu > 0 ? 2 : 1;
      k.rows += rows;
      k.nnz += (a >= 0 ? 6 : 3) * rows;
    }
  });
  int rows = 0, nnz = 0;
  for (int q = 0; q < jobs; ++q) {  // totals; count[q] becomes job q's first row and entry
    JobTally& k = count[q];
    rows += std::exchange(k.rows, rows);
    nnz += std::exchange(k.nnz, nnz);
  }
  const std::span<ContactConstraint> con = size_problem(nb, nc, rows, nnz, def, out);
  run_parts(threads, jobs, [&](int part) {
    fill_inv_mass(s, static_cast<int>(part_begin(nb, jobs, part)), static_cast<int>(part_begin(nb, jobs, part + 1)), out);
    int row = count[part].rows, at = count[part].nnz;
    const int c_end = static_cast<int>(part_begin(nc, jobs, part + 1));
    for (int c = static_cast<int>(part_begin(nc, jobs, part)); c < c_end; ++c) {
      prefetch_body_b(s, contacts, c, c_end);
      ContactConstraint& kc = con[static_cast<size_t>(c)];
      if (!write_contact(s, contacts[static_cast<size_t>(c)], def, kc, row, at, out) && count[part].bad < 0)
        count[part].bad = c;
    }
  });
  for (int q = 0; q < jobs; ++q)
    if (const int c = count[q].bad; c >= 0) {
      const ContactConstraint& kc = con[static_cast<size_t>(c)];
      ContactConstraints::check(c, kc.body_a, kc.body_b, kc.mu);
    }
}

/// assemble_jobs in one run, without its counting run, when every body owns columns (no shape
/// table) and one μ holds for every contact: the wall contacts come first (contacts sorted by
/// key), so with r rows per contact (2 when μ > 0, else 1) and W wall contacts, contact c's
/// first row is r·c and its first J entry r·(6c − 3·min(c, W)). Each job checks these premises
/// on its contacts and stops at the first that breaks them; false then, and the caller
/// assembles by assemble_jobs (which writes everything again).
bool assemble_direct(const BodyState& s, const std::vector<Contact>& contacts, const WorldDef& def,
                     LcpProblem& out, int threads, int jobs) {
  if (!s.shapes.empty() || contacts.empty()) return false;
  const int nb = static_cast<int>(s.size());
  const int nc = static_cast<int>(contacts.size());
  const bool friction = friction_of(contacts[0], def.contact) > 0;
  const int r = friction ? 2 : 1;
  const int walls = static_cast<int>(
      std::partition_point(contacts.begin(), contacts.end(), [](const Contact& ct) { return ct.body_a < 0; }) -
      contacts.begin());
  const std::span<ContactConstraint> con = size_problem(nb, nc, r * nc, r * (6 * nc - 3 * walls), def, out);
  const std::span<JobTally> job = job_tallies(jobs);
  run_parts(threads, jobs, [&](int part) {
    fill_inv_mass(s, static_cast<int>(part_begin(nb, jobs, part)), static_cast<int>(part_begin(nb, jobs, part + 1)), out);
    const int c0 = static_cast<int>(part_begin(nc, jobs, part));
    const int c_end = static_cast<int>(part_begin(nc, jobs, part + 1));
    int row = r * c0, at = r * (6 * c0 - 3 * std::min(c0, walls));
    JobTally& mine = job[static_cast<size_t>(part)];
    for (int c = c0; c < c_end; ++c) {
      prefetch_body_b(s, contacts, c, c_end);
      const Contact& ct = contacts[static_cast<size_t>(c)];
      if ((ct.body_a < 0) != (c < walls) || (friction_of(ct, def.contact) > 0) != friction) {
        mine.broken = true;
        return;
      }
      if (!write_contact(s, ct, def, con[static_cast<size_t>(c)], row, at, out) && mine.bad < 0) mine.bad = c;
    }
  });
  for (const JobTally& q : job)
    if (q.broken) return false;
  for (const JobTally& q : job)
    if (q.bad >= 0) {
      const ContactConstraint& kc = con[static_cast<size_t>(q.bad)];
      ContactConstraints::check(q.bad, kc.body_a, kc.body_b, kc.mu);
    }
  return true;
}

}  // namespace

void assemble_lcp(const BodyState& s, const std::vector<Contact>& contacts, const WorldDef& def,
                  LcpProblem& out, int threads) {
  out.structure.clear();  // until the structure below is complete (a check may throw)
  const int jobs = parts_for(threads, std::max(static_cast<long>(s.size()), static_cast<long>(contacts.size())), 4, 1024);
  if (jobs > 1) {
    if (!assemble_direct(s, contacts, def, out, threads, jobs)) assemble_jobs(s, contacts, def, out, threads, jobs);
  } else
    assemble_serial(s, contacts, def, out);
  // A = J M⁻¹ Jᵀ Δt is formed on demand only (LcpProblem::ensure_assembled_matrix). Emptied only
  // when formed: an empty SparseRowMatrix allocates its outer index, every step.
  if (out.A.rows() != 0 || out.A.cols() != 0 || out.A.nonZeros() != 0) out.A = SparseRowMatrix();
  // Every contact passed add()'s checks and got add()'s rows, with [0, +∞) on its normal row and
  // its μ on a tangent row coupled to it (fill_rows): the solver need not check that again.
  out.structure.set(out);
}

}  // namespace dc
