#include "solvers/prox_newton/pivot_finish.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "solvers/exact/lemke_pivoting.hpp"

namespace dc::solvers::prox {
namespace {

constexpr int kCoveringRetries = 2;

/// splitmix64 in [0, 1): the deterministic covering vectors (no global state).
double unit_random(uint64_t& s) {
  uint64_t z = (s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

bool is_normal_row(const LcpProblem& p, int i) {
  return !p.is_friction_row(i) && p.lo[i] == 0.0 && p.hi[i] == INFINITY;
}

/// Index of each row's first unknown in the split LCP (friction rows: λ⁺; λ⁻ and β follow).
struct Layout {
  std::vector<int> at;
  int size = 0;
};

std::optional<Layout> layout(const LcpProblem& p) {
  Layout l;
  l.at.assign(static_cast<size_t>(p.rows()), -1);
  for (int i = 0; i < p.rows(); ++i) {
    if (p.is_friction_row(i)) {
      if (!is_normal_row(p, p.normal_row[static_cast<size_t>(i)]) || !(p.mu[i] >= 0)) return std::nullopt;
      l.at[static_cast<size_t>(i)] = l.size;
      l.size += 3;
    } else {
      if (!is_normal_row(p, i)) return std::nullopt;
      l.at[static_cast<size_t>(i)] = l.size++;
    }
  }
  return l;
}

/// Lemke's z recomputed from its final basis: M_BB z_B = −q_B by a fresh LU with two
/// refinement steps (the tableau's round-off grows with the pivots); the tableau's z when the
/// basis matrix is singular.
Eigen::VectorXd refined(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const LemkePivoting& lp) {
  const int m = static_cast<int>(lp.active.size());
  if (m == 0) return lp.z;
  Eigen::MatrixXd Mbb(m, m);
  Eigen::VectorXd qb(m);
  for (int i = 0; i < m; ++i) {
    const int bi = lp.active[static_cast<size_t>(i)];
    qb[i] = -q[bi];
    for (int j = 0; j < m; ++j) Mbb(i, j) = M(bi, lp.active[static_cast<size_t>(j)]);
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(Mbb);
  if (!lu.isInvertible()) return lp.z;
  Eigen::VectorXd zb = lu.solve(qb);
  for (int step = 0; step < 2; ++step) zb += lu.solve(qb - Mbb * zb);
  if (!zb.allFinite()) return lp.z;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(M.rows());
  for (int i = 0; i < m; ++i) z[lp.active[static_cast<size_t>(i)]] = std::max(0.0, zb[i]);
  return z;
}

}  // namespace

int pivot_lcp_size(const LcpProblem& p) {
  const auto l = layout(p);
  return l ? l->size : -1;
}

PivotOutcome pivot_solve(const LcpProblem& p) {
  PivotOutcome out;
  const auto l = layout(p);
  if (!l) {
    out.why = "not a contact problem (a row is neither normal nor friction)";
    return out;
  }
  const int n = p.rows(), N = l->size;
  const double a = n > 0 ? p.A.diagonal().maxCoeff() : 0.0;
  const double c = n > 0 ? p.b.cwiseAbs().maxCoeff() : 0.0;
  if (!(a > 0 && std::isfinite(a))) {
    out.why = "no positive diagonal";
    return out;
  }
  if (!(c > 0 && std::isfinite(c))) {  // b = 0: λ = 0 solves
    out.lambda = Eigen::VectorXd::Zero(n);
    return out;
  }
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(N, N);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(N);
  const auto& at = l->at;
  // Row block of A's row i placed at LCP row r with sign sg: A_ij/a into the λ_n or λ⁺/λ⁻ columns.
  auto put_row = [&](int i, int r, double sg) {
    for (SparseRowMatrix::InnerIterator it(p.A, i); it; ++it) {
      const int j = static_cast<int>(it.col());
      const int cj = at[static_cast<size_t>(j)];
      const double v = sg * it.value() / a;
      M(r, cj) += v;
      if (p.is_friction_row(j)) M(r, cj + 1) -= v;
    }
    q[r] = sg * p.b[i] / c;
  };
  for (int i = 0; i < n; ++i) {
    const int r = at[static_cast<size_t>(i)];
    if (!p.is_friction_row(i)) {
      put_row(i, r, 1.0);
      continue;
    }
    put_row(i, r, 1.0);
    put_row(i, r + 1, -1.0);
    M(r, r + 2) = 1.0;  // + β
    M(r + 1, r + 2) = 1.0;
    M(r + 2, at[static_cast<size_t>(p.normal_row[static_cast<size_t>(i)])]) = p.mu[i];
    M(r + 2, r) = -1.0;
    M(r + 2, r + 1) = -1.0;
  }
  // Covering vector 1, then (Lemke also ends on a ray on solvable degenerate problems, e.g.
  // two contacts per box face) deterministic ones in [0.1, 1).
  LemkePivoting lp;
  uint64_t state = 0x5eed1e3eull + static_cast<uint64_t>(N);
  for (int attempt = 0; attempt < 1 + kCoveringRetries; ++attempt) {
    Eigen::VectorXd d = Eigen::VectorXd::Ones(N);
    if (attempt > 0)
      for (int i = 0; i < N; ++i) d[i] = 0.1 + 0.9 * unit_random(state);
    lp = lemke_pivoting(M, q, d, 50 * N + 10);
    out.pivots += lp.pivots;
    out.why = lp.why;
    if (lp.outcome == LemkePivoting::Outcome::Solved) break;
  }
  if (lp.outcome != LemkePivoting::Outcome::Solved) return out;
  const Eigen::VectorXd z = refined(M, q, lp);
  Eigen::VectorXd lambda(n);
  const double s = c / a;
  for (int i = 0; i < n; ++i) {
    const int r = at[static_cast<size_t>(i)];
    lambda[i] = p.is_friction_row(i) ? s * (z[r] - z[r + 1]) : s * z[r];
  }
  if (lambda.allFinite()) out.lambda = std::move(lambda);
  return out;
}

}  // namespace dc::solvers::prox
