// pgs-colored's input checks on threads (pgs_colored_input.hpp). Every condition of
// LcpProblem::validate and check_input is tested here too, so "all passed" here means the
// serial checks pass; any failure hands over to them for the message.
#include "solvers/pgs_colored/pgs_colored_input.hpp"

#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

#include "solvers/solver_common.hpp"

namespace dc::colored {
namespace {

/// The size checks of validate and check_input (O(1)): false when one fails.
bool sizes_ok(const LcpProblem& p, const Eigen::VectorXd& lambda0) {
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

/// Row i of validate's per-row checks (b, coupling, μ, bounds) and λ⁰_i finite.
bool row_ok(const LcpProblem& p, const Eigen::VectorXd& lambda0, int i) {
  const int n = p.rows();
  bool ok = std::isfinite(p.b[i]) && (lambda0.size() == 0 || std::isfinite(lambda0[i]));
  const int nr = p.normal_row[static_cast<size_t>(i)];
  if (nr >= 0) {
    ok = ok && nr < n && p.normal_row[static_cast<size_t>(nr)] < 0 && p.mu[i] >= 0 && std::isfinite(p.mu[i]);
  } else {
    const double lo = p.lo[i], hi = p.hi[i];
    ok = ok && !std::isnan(lo) && !std::isnan(hi) && !(lo > hi) && lo != INFINITY && hi != -INFINITY;
  }
  if (i < p.A.outerSize())  // (A is empty when matrix-free)
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

}  // namespace

std::optional<SolveResult> check_input(const LcpProblem& p, const Eigen::VectorXd& lambda0, const std::string& solver,
                                       int threads, Eigen::VectorXd& zeros, const Eigen::VectorXd*& start,
                                       std::vector<int>& owner) {
  auto serial = [&]() -> std::optional<SolveResult> {
    if (auto bad = solvers::check_input(p, lambda0, solver, zeros)) return bad;
    start = &zeros;  // (not reached when the checks above are complete)
    return std::nullopt;
  };
  if (!sizes_ok(p, lambda0)) return serial();
  const int n = p.rows(), nc = p.constraints.size();
  // owner[r] = the contact claiming row r. The contacts own n rows in all (sizes_ok), so each
  // row is owned once exactly when no row is claimed twice: then every claim reads back its
  // own contact. A row claimed twice keeps one writer's index and the other contact sees it.
  // Only claimed rows are read back, after the claims: stale entries are never read.
  owner.resize(static_cast<size_t>(nc > 0 ? n : 0));
  if (lambda0.size() == 0) zeros.resize(n);
  // The three scans as orphaned static loops: on one thread no parallel region is entered
  // (libgomp allocates a team even for a region that runs serially).
  std::atomic<bool> ok{true};  // cleared by a thread whose share failed (an order-free AND)
  auto scans = [&] {
    bool mine = true;
#pragma omp for schedule(static) nowait
    for (int i = 0; i < n; ++i) {
      mine = mine && row_ok(p, lambda0, i);
      if (lambda0.size() == 0) zeros[i] = 0.0;
    }
#pragma omp for schedule(static)
    for (int c = 0; c < nc; ++c) {
      const bool good = contact_ok(p, c);
      mine = mine && good;
      if (!good) continue;
      const ContactConstraint& k = p.constraints[c];
      std::atomic_ref<int>(owner[static_cast<size_t>(k.normal_row)]).store(c, std::memory_order_relaxed);
      if (k.has_friction()) std::atomic_ref<int>(owner[static_cast<size_t>(k.tangent_row)]).store(c, std::memory_order_relaxed);
    }
    // (the barrier of the loop above orders the claims before the read-back)
#pragma omp for schedule(static)
    for (int c = 0; c < nc; ++c) {
      const ContactConstraint& k = p.constraints[c];
      if (k.normal_row < 0 || k.normal_row >= n || k.tangent_row >= n) continue;  // failed above
      mine = mine && std::atomic_ref<int>(owner[static_cast<size_t>(k.normal_row)]).load(std::memory_order_relaxed) == c;
      if (k.has_friction())
        mine = mine && std::atomic_ref<int>(owner[static_cast<size_t>(k.tangent_row)]).load(std::memory_order_relaxed) == c;
    }
    if (!mine) ok.store(false, std::memory_order_relaxed);
  };
  if (threads > 1) {
#pragma omp parallel num_threads(threads)
    scans();
  } else {
    scans();
  }
  if (!ok.load(std::memory_order_relaxed)) return serial();
  start = lambda0.size() == 0 ? &zeros : &lambda0;
  return std::nullopt;
}

}  // namespace dc::colored
