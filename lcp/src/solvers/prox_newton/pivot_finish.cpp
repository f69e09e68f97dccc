#include "solvers/prox_newton/pivot_finish.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
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

namespace {

/// The contacts of p: each row's normal row (itself for a normal row) and each normal row's
/// rows (itself first, then its friction rows ascending).
struct Contacts {
  std::vector<int> head;                   ///< per row: its contact's normal row
  std::vector<std::vector<int>> members;   ///< per normal row: the contact's rows
};

Contacts contacts(const LcpProblem& p) {
  Contacts c;
  const auto n = static_cast<size_t>(p.rows());
  c.head.resize(n);
  c.members.resize(n);
  for (size_t i = 0; i < n; ++i) {
    c.head[i] = p.is_friction_row(static_cast<int>(i)) ? p.normal_row[i] : static_cast<int>(i);
    c.members[static_cast<size_t>(c.head[i])].push_back(static_cast<int>(i));
  }
  return c;
}

/// Split-LCP unknowns of a contact: 1 for the normal row, 3 per friction row.
int split_size(const std::vector<int>& members) { return 1 + 3 * (static_cast<int>(members.size()) - 1); }

}  // namespace

std::vector<int> local_pivot_rows(const LcpProblem& p, const Eigen::VectorXd& lambda, double threshold, int rings,
                                  int max_size) {
  if (pivot_lcp_size(p) < 0) return {};
  const int n = p.rows();
  const Contacts c = contacts(p);
  const Eigen::VectorXd w = p.A * lambda + Eigen::VectorXd(p.b);
  std::vector<char> in(static_cast<size_t>(n), 0);  // per normal row: contact in the set
  std::vector<int> ring;                              // the normal rows added last
  int size = 0;
  for (int i = 0; i < n; ++i) {
    const double r = std::abs(natural_map_row(p, lambda, w, i));
    const auto h = static_cast<size_t>(c.head[static_cast<size_t>(i)]);
    if (!(r > threshold) || in[h]) continue;
    in[h] = 1;
    ring.push_back(static_cast<int>(h));
    size += split_size(c.members[h]);
  }
  if (size > max_size) return {};
  for (int k = 0; k < rings && !ring.empty(); ++k) {
    std::vector<int> next;
    int grown = size;
    for (const int h : ring)
      for (const int i : c.members[static_cast<size_t>(h)])
        for (SparseRowMatrix::InnerIterator it(p.A, i); it; ++it) {
          const auto g = static_cast<size_t>(c.head[static_cast<size_t>(it.col())]);
          if (in[g]) continue;
          in[g] = 2;  // provisional: this ring
          next.push_back(static_cast<int>(g));
          grown += split_size(c.members[g]);
        }
    const bool fits = grown <= max_size;
    for (const int g : next) in[static_cast<size_t>(g)] = fits ? 1 : 0;
    if (!fits) {
      // The ring in part: its contacts nearest the set first (most coupled entries), ties by row.
      std::vector<std::pair<int, int>> order;  // (−couplings, normal row)
      for (const int g : next) {
        int links = 0;
        for (const int i : c.members[static_cast<size_t>(g)])
          for (SparseRowMatrix::InnerIterator it(p.A, i); it; ++it)
            links += in[static_cast<size_t>(c.head[static_cast<size_t>(it.col())])] == 1;
        order.emplace_back(-links, g);
      }
      std::sort(order.begin(), order.end());
      for (const auto& [links, g] : order) {
        const int add = split_size(c.members[static_cast<size_t>(g)]);
        if (size + add > max_size) break;
        in[static_cast<size_t>(g)] = 1;
        size += add;
      }
      break;
    }
    size = grown;
    ring = std::move(next);
  }
  std::vector<int> rows;
  for (int i = 0; i < n; ++i)
    if (in[static_cast<size_t>(c.head[static_cast<size_t>(i)])]) rows.push_back(i);
  return rows;
}

PivotOutcome local_pivot_solve(const LcpProblem& p, const Eigen::VectorXd& lambda, const std::vector<int>& rows,
                               double shift) {
  const int n = p.rows(), m = static_cast<int>(rows.size());
  const double delta = shift * (n > 0 ? p.A.diagonal().maxCoeff() : 0.0);
  std::vector<int> local(static_cast<size_t>(n), -1);
  for (int k = 0; k < m; ++k) local[static_cast<size_t>(rows[static_cast<size_t>(k)])] = k;
  // b_S + A_{S,S̄} λ_S̄: the fixed rows' impulses enter as a constant velocity [m/s].
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd bs(m);
  for (int k = 0; k < m; ++k) {
    const int i = rows[static_cast<size_t>(k)];
    double bi = p.b[i];
    for (SparseRowMatrix::InnerIterator it(p.A, i); it; ++it) {
      const int lj = local[static_cast<size_t>(it.col())];
      if (lj >= 0)
        entries.emplace_back(k, lj, it.value());
      else
        bi += it.value() * lambda[it.col()];
    }
    entries.emplace_back(k, k, delta);
    bs[k] = bi - delta * lambda[i];
  }
  SparseRowMatrix As(m, m);
  As.setFromTriplets(entries.begin(), entries.end());
  LcpProblem sub = LcpProblem::standard(As, bs);
  for (int k = 0; k < m; ++k) {
    const int i = rows[static_cast<size_t>(k)];
    sub.lo[k] = p.lo[i];
    sub.hi[k] = p.hi[i];
    sub.mu[k] = p.mu[i];
    const int nr = p.normal_row[static_cast<size_t>(i)];
    sub.normal_row[static_cast<size_t>(k)] = nr < 0 ? -1 : local[static_cast<size_t>(nr)];
    if (nr >= 0 && local[static_cast<size_t>(nr)] < 0) return {std::nullopt, 0, "rows not closed under coupling"};
  }
  PivotOutcome out = pivot_solve(sub);
  if (!out.lambda) return out;
  Eigen::VectorXd full = lambda;
  for (int k = 0; k < m; ++k) full[rows[static_cast<size_t>(k)]] = (*out.lambda)[k];
  out.lambda = std::move(full);
  return out;
}

}  // namespace dc::solvers::prox
