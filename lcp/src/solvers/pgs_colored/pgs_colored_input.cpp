// pgs-colored's input checks on threads (pgs_colored_input.hpp). Every condition of
// LcpProblem::validate and check_input is tested here too, so "all passed" here means the
// serial checks pass; any failure hands over to them for the message.
#include "solvers/pgs_colored/pgs_colored_input.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "dc/core/work_team.hpp"
#include "solvers/solver_common.hpp"

namespace dc::colored {
namespace {

/// The size checks of validate and check_input (O(1)): false when one fails.
bool sizes_ok(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0) {
  const int n = p.rows();
  const bool matrix_free = p.A.rows() == 0 && p.A.cols() == 0 && n > 0;
  if (matrix_free && !p.has_jacobian()) return false;
  if (!matrix_free && (p.A.rows() != n || p.A.cols() != n)) return false;
  if (p.lo.size() != n || p.hi.size() != n || p.mu.size() != n || static_cast<int>(p.normal_row.size()) != n)
    return false;
  if (p.J.rows() > 0 && (p.J.rows() != n || p.inv_mass.size() != p.J.cols() || !(p.dt > 0))) return false;
  if (!p.constraints.empty() && p.constraints.rows() != n) return false;
  return lambda0.size() == 0 || lambda0.size() == n;
}

/// x is ±∞ or NaN, on the exponent bits (integer operations: the loops below vectorise).
inline bool not_finite(double x) {
  constexpr std::uint64_t kExp = 0x7ff0000000000000ull;
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return (bits & kExp) == kExp;
}

/// rows_ok's checks of rows [i0, i1) but A's, with or without λ⁰: every condition of each row
/// evaluated and AND-ed without a branch (a normal row's coupling read at a clamped index, its
/// verdict chosen by the row's kind), so the loop has no data-dependent jumps. kOwned: the
/// contacts' pass vouches that each coupled row's normal row is a normal row (check_input), so
/// that read is left out and the loop has no gather.
template <bool kLambda0, bool kOwned>
bool rows_ok_plain(const LcpProblem& p, const double* l0, int i0, int i1) {
  const int n = p.rows();
  const double* b = p.b.data();
  const int* nrow = p.normal_row.data();
  const double* mu = p.mu.data();
  const double* lo = p.lo.data();
  const double* hi = p.hi.data();
  if constexpr (kOwned) {  // the conditions as 0/1 integers, OR-ed: a loop the compiler vectorises
    unsigned bad = 0;
    for (int i = i0; i < i1; ++i) {
      const int nr = nrow[i];
      const double m = mu[i], l = lo[i], h = hi[i];
      unsigned row = not_finite(b[i]);
      if constexpr (kLambda0) row |= not_finite(l0[i]);
      const unsigned coupled = (nr >= n) | !(m >= 0) | not_finite(m);
      const unsigned bounds = (l != l) | (h != h) | (l > h) | (l == INFINITY) | (h == -INFINITY);
      row |= nr >= 0 ? coupled : bounds;
      bad |= row;
    }
    return bad == 0;
  }
  bool ok = true;
  for (int i = i0; i < i1; ++i) {
    bool row = !not_finite(b[i]);
    if constexpr (kLambda0) row &= !not_finite(l0[i]);
    const int nr = nrow[i];
    const bool in = (nr >= 0) & (nr < n);
    const bool coupled = in & (nrow[in ? nr : 0] < 0) & (mu[i] >= 0) & !not_finite(mu[i]);
    const double l = lo[i], h = hi[i];
    const bool bounds = !std::isnan(l) & !std::isnan(h) & !(l > h) & (l != INFINITY) & (h != -INFINITY);
    row &= nr >= 0 ? coupled : bounds;
    ok &= row;
  }
  return ok;
}

/// validate's per-row checks (b, coupling, μ, bounds, A) and λ⁰_i finite, on rows [i0, i1);
/// owned as rows_ok_plain's kOwned.
bool rows_ok(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0, int i0, int i1, bool owned) {
  const double* l0 = lambda0.data();
  bool ok = lambda0.size() == 0 ? (owned ? rows_ok_plain<false, true>(p, nullptr, i0, i1)
                                         : rows_ok_plain<false, false>(p, nullptr, i0, i1))
                                : (owned ? rows_ok_plain<true, true>(p, l0, i0, i1)
                                         : rows_ok_plain<true, false>(p, l0, i0, i1));
  const int a_rows = std::min(i1, static_cast<int>(p.A.outerSize()));  // (0 when matrix-free)
  for (int i = i0; i < a_rows && ok; ++i)
    for (SparseRowMatrix::InnerIterator it(p.A, i); it && ok; ++it) ok = std::isfinite(it.value());
  return ok;
}

/// The checks that a problem stamped by its builder (StructureStamp) can still fail, on rows
/// [i0, i1): b, λ⁰ and A finite — the values of the step, not the structure.
bool values_ok(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0, int i0, int i1) {
  const double* b = p.b.data();
  const double* l0 = lambda0.data();
  unsigned bad = 0;  // OR-ed 0/1 integers: a loop the compiler vectorises
  if (lambda0.size() == 0)
    for (int i = i0; i < i1; ++i) bad |= not_finite(b[i]);
  else
    for (int i = i0; i < i1; ++i) bad |= not_finite(b[i]) | not_finite(l0[i]);
  bool ok = bad == 0;
  const int a_rows = std::min(i1, static_cast<int>(p.A.outerSize()));  // (0 when matrix-free)
  for (int i = i0; i < a_rows && ok; ++i)
    for (SparseRowMatrix::InnerIterator it(p.A, i); it && ok; ++it) ok = std::isfinite(it.value());
  return ok;
}

/// Contact c's checks of validate_constraints, except that each row is owned once (the
/// owners pass below).
bool contact_ok(const LcpProblem& p, int c) {
  const ContactConstraint& k = p.constraints[c];
  const int n = p.rows(), bodies = static_cast<int>(p.J.cols() / 3);
  if (p.J.rows() > 0 && (k.body_b >= bodies || k.body_a >= bodies)) return false;
  if (k.normal_row < 0 || k.normal_row >= n || p.normal_row[static_cast<size_t>(k.normal_row)] >= 0) return false;
  if (k.has_friction() != (k.mu > 0)) return false;
  if (k.has_friction()) {
    if (k.tangent_row >= n) return false;
    const size_t t = static_cast<size_t>(k.tangent_row);
    if (p.normal_row[t] != k.normal_row || p.mu[k.tangent_row] != k.mu) return false;
  }
  return true;
}

/// Contacts [c0, c1) claim rows in strictly increasing order (normal, then tangent; each contact's
/// after the previous contact's, contact c0 − 1 included): then no row is claimed twice. The
/// engine numbers rows this way (ContactConstraints::add).
bool rows_increase(const ContactConstraints& cons, int c0, int c1) {
  int last = c0 > 0 ? std::max(cons[c0 - 1].normal_row, cons[c0 - 1].tangent_row) : -1;
  bool up = true;
  for (int c = c0; c < c1; ++c) {
    const ContactConstraint& k = cons[c];
    up &= k.normal_row > last && (k.tangent_row < 0 || k.tangent_row > k.normal_row);
    last = std::max(k.normal_row, k.tangent_row);
  }
  return up;
}

/// No row is claimed by two contacts (for contacts that passed contact_ok): owner[r] = the contact
/// claiming row r, then every claim reads back its own contact. The contacts claim n rows in all
/// (check_input counts them), so each row is owned once exactly when no row is claimed twice: a row claimed
/// twice keeps one writer's index and the other contact sees it. Only claimed rows are read back,
/// after the claims: stale entries are never read.
bool claims_unique(const LcpProblem& p, int threads, int chunk, std::vector<int>& owner) {
  const int n = p.rows(), nc = p.constraints.size();
  owner.resize(static_cast<size_t>(n));
  const int chunks = (nc + chunk - 1) / chunk;
  WorkTeam& team = calling_thread_team();
  team.for_parts(threads, chunks, [&](int part) {
    const int c0 = part * chunk, c1 = std::min(nc, c0 + chunk);
    for (int c = c0; c < c1; ++c) {
      const ContactConstraint& k = p.constraints[c];
      std::atomic_ref<int>(owner[static_cast<size_t>(k.normal_row)]).store(c, std::memory_order_relaxed);
      if (k.has_friction()) std::atomic_ref<int>(owner[static_cast<size_t>(k.tangent_row)]).store(c, std::memory_order_relaxed);
    }
  });
  // (the end of the run above orders the claims before the read-back)
  std::atomic<bool> ok{true};
  team.for_parts(threads, chunks, [&](int part) {
    bool mine = true;
    const int c0 = part * chunk, c1 = std::min(nc, c0 + chunk);
    for (int c = c0; c < c1; ++c) {
      const ContactConstraint& k = p.constraints[c];
      mine = mine && std::atomic_ref<int>(owner[static_cast<size_t>(k.normal_row)]).load(std::memory_order_relaxed) == c;
      if (k.has_friction())
        mine = mine && std::atomic_ref<int>(owner[static_cast<size_t>(k.tangent_row)]).load(std::memory_order_relaxed) == c;
    }
    if (!mine) ok.store(false, std::memory_order_relaxed);
  });
  return ok.load(std::memory_order_relaxed);
}

}  // namespace

std::optional<SolveResult> check_input(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0, const std::string& solver,
                                       int threads, Eigen::VectorXd& zeros, const double*& start,
                                       std::vector<int>& owner, bool& trusted) {
  auto serial = [&]() -> std::optional<SolveResult> {
    if (auto bad = solvers::check_input(p, lambda0, solver, zeros)) return bad;
    start = lambda0.size() == 0 ? zeros.data() : lambda0.data();  // (the checks passed: λ⁰ is valid as given)
    return std::nullopt;
  };
  trusted = false;
  if (!sizes_ok(p, lambda0)) return serial();
  const int n = p.rows(), nc = p.constraints.size();
  if (lambda0.size() == 0) zeros.resize(n);
  constexpr int kRowChunk = 1024, kContactChunk = 1024;
  const int row_chunks = (n + kRowChunk - 1) / kRowChunk, contact_chunks = (nc + kContactChunk - 1) / kContactChunk;
  if (p.structure.holds(p)) {
    // Valid by construction but for the values of the step: those alone, the full checks (and
    // their message) when one fails.
    std::atomic<bool> ok{true};
    calling_thread_team().for_parts(threads, row_chunks, [&](int part) {
      const int i = part * kRowChunk, i1 = std::min(n, i + kRowChunk);
      if (!values_ok(p, lambda0, i, i1)) ok.store(false, std::memory_order_relaxed);
      if (lambda0.size() == 0) std::fill(zeros.data() + i, zeros.data() + i1, 0.0);
    });
    if (!ok.load(std::memory_order_relaxed)) return serial();
    trusted = true;
    start = lambda0.size() == 0 ? zeros.data() : lambda0.data();
    return std::nullopt;
  }
  // The scans by chunks on the calling thread's team: the rows, and the contacts with whether
  // their rows increase; where they do not, the claims of claims_unique.
  std::atomic<bool> ok{true};        // cleared by a chunk that failed (an order-free AND)
  std::atomic<bool> increase{true};  // cleared by a chunk whose contacts' rows do not increase
  std::atomic<long> claimed{0};      // rows the contacts claim (each chunk adds its count)
  // With contacts, a coupled row's normal row is checked through its contact instead of by the
  // row scan: when every contact passes contact_ok and the contacts claim n rows, each once, each
  // row is a contact's normal row (coupling < 0) or its tangent row, coupled (contact_ok) to
  // that contact's normal row, a normal row. Without contacts the row scan reads it.
  const bool owned = nc > 0;
  calling_thread_team().for_parts(threads, row_chunks + contact_chunks, [&](int part) {
    bool mine = true;
    if (part < row_chunks) {
      const int i = part * kRowChunk, i1 = std::min(n, i + kRowChunk);
      mine = rows_ok(p, lambda0, i, i1, owned);
      if (lambda0.size() == 0) std::fill(zeros.data() + i, zeros.data() + i1, 0.0);
    } else {
      const int c0 = (part - row_chunks) * kContactChunk, c1 = std::min(nc, c0 + kContactChunk);
      long rows = 0;
      for (int c = c0; c < c1; ++c) {
        mine = mine && contact_ok(p, c);
        rows += p.constraints[c].has_friction() ? 2 : 1;
      }
      claimed.fetch_add(rows, std::memory_order_relaxed);
      if (!rows_increase(p.constraints, c0, c1)) increase.store(false, std::memory_order_relaxed);
    }
    if (!mine) ok.store(false, std::memory_order_relaxed);
  });
  if (!ok.load(std::memory_order_relaxed)) return serial();
  if (owned && claimed.load(std::memory_order_relaxed) != n) return serial();
  if (!increase.load(std::memory_order_relaxed) && !claims_unique(p, threads, kContactChunk, owner)) return serial();
  start = lambda0.size() == 0 ? zeros.data() : lambda0.data();
  return std::nullopt;
}

}  // namespace dc::colored
