// pgs-colored's layout scans on the team (layout_scan.hpp).
#include "solvers/pgs_colored/setup/layout_scan.hpp"

#include <algorithm>
#include <limits>

#include "dc/core/work_team.hpp"
#include "solvers/pgs_manifold_block.hpp"

namespace dc::colored {
namespace {

/// True when rows i0 and i1 of J are stored alike (the engine's storage: the columns of the
/// contact's bodies in order) and their linear parts (the normal) are bit-equal.
bool same_normal(const LcpProblem& p, int i0, int i1) {
  auto extent = [&](int i) {
    const int q0 = p.J.outerIndexPtr()[i];
    return (p.J.isCompressed() ? p.J.outerIndexPtr()[i + 1] : q0 + p.J.innerNonZeroPtr()[i]) - q0;
  };
  const int n = extent(i0);
  if (n != extent(i1) || (n != 3 && n != 6)) return false;
  const int q0 = p.J.outerIndexPtr()[i0], q1 = p.J.outerIndexPtr()[i1];
  const int* c0 = p.J.innerIndexPtr() + q0;
  const int* c1 = p.J.innerIndexPtr() + q1;
  const double* v0 = p.J.valuePtr() + q0;
  const double* v1 = p.J.valuePtr() + q1;
  for (int s = 0; s < n; ++s)
    if (c0[s] != c1[s]) return false;
  for (int s = 0; s < n; s += 3)
    if (c0[s] % 3 != 0 || c0[s + 1] != c0[s] + 1 || c0[s + 2] != c0[s] + 2 || v0[s] != v1[s] || v0[s + 1] != v1[s + 1])
      return false;
  return true;
}

/// The conditioning test of "pgs"'s pairing (manifold_block_conditioned) on normal rows i0 and i1
/// stored alike (same_normal): A_00, A_11 and A_01 summed in slot order as pack_row and fill_pair
/// sum them, so the pairs are "pgs"'s.
bool block_conditioned(const LcpProblem& p, int i0, int i1) {
  const int q0 = p.J.outerIndexPtr()[i0], q1 = p.J.outerIndexPtr()[i1];
  const int n = (p.J.isCompressed() ? p.J.outerIndexPtr()[i0 + 1] : q0 + p.J.innerNonZeroPtr()[i0]) - q0;
  const int* col = p.J.innerIndexPtr() + q0;
  const double* v0 = p.J.valuePtr() + q0;
  const double* v1 = p.J.valuePtr() + q1;
  double a00 = 0.0, a11 = 0.0, a01 = 0.0;
  for (int s = 0; s < n; ++s) {
    const double im = p.inv_mass[col[s]];
    const double r0 = 0.0 + v0[s], r1 = 0.0 + v1[s];
    const double m0 = r0 * im * p.dt, m1 = r1 * im * p.dt;
    a00 += r0 * m0;
    a11 += r1 * m1;
    a01 += r0 * m1;
  }
  return solvers::manifold_block_conditioned(a00, a11, a01);
}

/// may_pair's first test, the one most contacts fail: the same bodies, different features and
/// friction on both or neither.
inline bool same_bodies(const ContactConstraint& k0, const ContactConstraint& k1) {
  return k1.body_a == k0.body_a && k1.body_b == k0.body_b && k1.feature != k0.feature &&
         k1.has_friction() == k0.has_friction();
}

/// may_pair's tests of the rows, after same_bodies.
bool rows_pair(const LcpProblem& p, const ContactConstraint& k0, const ContactConstraint& k1) {
  const bool fr = k0.has_friction();
  if (fr && (k0.tangent_row != k0.normal_row + 1 || k1.tangent_row != k1.normal_row + 1)) return false;
  return k1.normal_row == k0.normal_row + (fr ? 2 : 1) && same_normal(p, k0.normal_row, k1.normal_row) &&
         block_conditioned(p, k0.normal_row, k1.normal_row);
}

/// Contacts per part of the scan: fewer make a team run cost more than it saves.
constexpr int kMinContacts = 1024;

}  // namespace

bool may_pair(const LcpProblem& p, int c) {
  const ContactConstraint* k = p.constraints.contacts().data() + c;
  return same_bodies(k[0], k[1]) && rows_pair(p, k[0], k[1]);
}

int scan_contacts(const LcpProblem& p, int bodies, int threads, std::vector<std::uint8_t>& dynamic,
                  std::vector<int>& partner) {
  const ContactConstraints& cons = p.constraints;
  const int nc = cons.size();
  dynamic.resize(static_cast<size_t>(bodies));
  partner.resize(static_cast<size_t>(nc));
  const int parts = std::max(1, std::min(threads, nc / kMinContacts));
  // A body is dynamic when one of its three M⁻¹ entries is not 0: per body, without branches or
  // divisions (this pass is over all bodies, which outnumber the contacts of a sparse pile).
  const int ncols = static_cast<int>(p.inv_mass.size());
  const double* im = p.inv_mass.data();
  std::uint8_t* dyn = dynamic.data();
  const int whole = std::min(ncols / 3, bodies);
  int first_bad[64];  // per part (parts ≤ the team's size)
  bool paired[64];
  const int used = std::min(parts, 64);
  const ContactConstraint* const k = cons.contacts().data();
  int* const mate = partner.data();
  calling_thread_team().for_parts(threads, used, [&](int part) {
    const int k0 = static_cast<int>(static_cast<long long>(bodies) * part / used);
    const int k1 = static_cast<int>(static_cast<long long>(bodies) * (part + 1) / used);
    for (int b = k0; b < std::min(k1, whole); ++b)
      dyn[b] = static_cast<std::uint8_t>((im[3 * b] != 0.0) | (im[3 * b + 1] != 0.0) | (im[3 * b + 2] != 0.0));
    for (int b = std::max(k0, whole); b < k1; ++b) {  // a body short of its three entries
      bool any = false;
      for (int c = 3 * b; c < std::min(ncols, 3 * b + 3); ++c) any |= im[c] != 0.0;
      dyn[b] = static_cast<std::uint8_t>(any);
    }
    // Locals: the stores into mate could otherwise alias the captured ints.
    const int count = nc;
    const int c0 = static_cast<int>(static_cast<long long>(count) * part / used);
    const int c1 = static_cast<int>(static_cast<long long>(count) * (part + 1) / used);
    int bad = -1;
    for (int c = c0; c < c1; ++c) {
      const int i = k[c].normal_row;
      if (p.is_friction_row(i) || p.lo[i] != 0.0 || p.hi[i] != std::numeric_limits<double>::infinity()) {
        bad = c;
        break;
      }
    }
    int* const out = mate;
    std::fill(out + c0, out + c1, -1);
    bool some = false;
    for (int c = c0; c < std::min(c1, count - 1); ++c)
      if (same_bodies(k[c], k[c + 1]) && rows_pair(p, k[c], k[c + 1])) {
        out[c] = c + 1;
        some = true;
      }
    first_bad[part] = bad;
    paired[part] = some;
  });
  for (int part = 0; part < used; ++part)
    if (first_bad[part] >= 0) return first_bad[part];
  if (std::none_of(paired, paired + used, [](bool b) { return b; })) return -1;
  // Greedy in contact order: a pair's second point is not the first point of another.
  for (int c = 0; c + 1 < nc; ++c)
    if (mate[c] >= 0) mate[++c] = -2;
  return -1;
}

}  // namespace dc::colored
