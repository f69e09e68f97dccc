#include "solvers/exact/lcp_proofs.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "solvers/exact/lemke_pivoting.hpp"

namespace dc::solvers {
namespace {

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

bool check_farkas_certificate(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Eigen::VectorXd& y,
                              std::string& detail) {
  const auto n = q.size();
  if (y.size() != n || M.rows() != n || M.cols() != n || !y.allFinite() || y.minCoeff() < 0) {
    detail = "certificate rejected: y must be finite and >= 0";
    return false;
  }
  // Sums in long double; (Mᵀy)_j must be ≤ 0 up to the round-off of its own sum.
  long double qy = 0, qabs = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    qy += static_cast<long double>(q[i]) * y[i];
    qabs += std::abs(static_cast<long double>(q[i])) * y[i];
  }
  double worst = 0.0;  // largest (Mᵀy)_j / Σ_i |M_ij| y_i
  long double excess = 0;  // Σ_j max(0, (Mᵀy)_j)
  for (Eigen::Index j = 0; j < n; ++j) {
    long double g = 0, a = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      g += static_cast<long double>(M(i, j)) * y[i];
      a += std::abs(static_cast<long double>(M(i, j))) * y[i];
    }
    if (g > 0) {
      excess += g;
      worst = std::max(worst, static_cast<double>(g / a));
    }
  }
  if (!(qy < 0) || -qy < 1e-9L * qabs) {
    detail = "certificate rejected: q'y = " + fmt(static_cast<double>(qy)) + " is not clearly negative";
    return false;
  }
  if (worst > 1e-12) {
    detail = "certificate rejected: (M'y)_j > 0 by " + fmt(worst) + " of its magnitude";
    return false;
  }
  detail = "Farkas certificate y >= 0 with M'y <= 0 and q'y = " + fmt(static_cast<double>(qy)) +
           " < 0: y'(Mz + q) < 0 for every z >= 0";
  if (excess > 0)  // (Mᵀy)_j within round-off above 0: exact only for ‖z‖₁ below this bound
    detail += " with ||z||_1 < " + fmt(static_cast<double>(-qy / excess));
  return true;
}

FarkasCertificate find_farkas_certificate(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  FarkasCertificate c;
  const int n = static_cast<int>(q.size());
  if (n > kFarkasMaxN) {
    c.detail = "no certificate search for n > " + std::to_string(kFarkasMaxN);
    return c;
  }
  // The LP  y ≥ 0, Mᵀy ≤ 0, qᵀy ≤ −1  (constraints A y ≤ b, A = [Mᵀ; qᵀ], b = [0; −1]) as the
  // LCP of its KKT conditions in (y, x):  u = Aᵀx ≥ 0 ⊥ y ≥ 0,  v = b − A y ≥ 0 ⊥ x ≥ 0,
  // matrix [[0, Aᵀ], [−A, 0]] (skew-symmetric). Its dual part is always feasible (x = 0), so
  // it is solvable iff a certificate exists, and Lemke's method decides which.
  const double ms = std::max(M.cwiseAbs().maxCoeff(), 1e-300), qs = std::max(q.cwiseAbs().maxCoeff(), 1e-300);
  const int N = 2 * n + 1;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(N, N);
  G.block(0, n, n, n) = M / ms;
  G.block(0, 2 * n, n, 1) = q / qs;
  G.block(n, 0, n, n) = -(M / ms).transpose();
  G.block(2 * n, 0, 1, n) = -(q / qs).transpose();
  Eigen::VectorXd qg = Eigen::VectorXd::Zero(N);
  qg[N - 1] = -1.0;
  const LemkePivoting lp = lemke_pivoting(G, qg, Eigen::VectorXd::Ones(N), 50 * N + 10);
  if (lp.outcome == LemkePivoting::Outcome::Ray) {
    c.detail = "no Farkas certificate: the LP y >= 0, M'y <= 0, q'y < 0 is infeasible, so {z >= 0, Mz + q >= 0} "
               "is not empty";
    return c;
  }
  if (lp.outcome == LemkePivoting::Outcome::Stopped) {
    c.detail = "certificate search stopped (" + lp.why + ")";
    return c;
  }
  c.y = lp.z.head(n);  // the scaling of M and q by positive constants keeps y a certificate
  c.found = check_farkas_certificate(M, q, c.y, c.detail);
  return c;
}

BasisEnumeration enumerate_complementary_bases(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                                               const std::function<bool(const Eigen::VectorXd&)>& accept) {
  BasisEnumeration e;
  const int n = static_cast<int>(q.size());
  if (n > kEnumerateMaxN) {
    e.detail = "no enumeration for n > " + std::to_string(kEnumerateMaxN);
    return e;
  }
  // Bounded-size (stack) matrices: 2ⁿ small factorisations without a heap allocation each.
  constexpr int kMax = kEnumerateMaxN;
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMax, kMax>;
  using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMax, 1>;
  int idx[kMax];
  SmallVec z(n), w(n);
  for (unsigned long mask = 0; mask < (1ul << n); ++mask) {
    ++e.bases;
    int m = 0;
    for (int i = 0; i < n; ++i)
      if (mask & (1ul << i)) idx[m++] = i;
    z.setZero();
    if (m > 0) {
      Small Maa(m, m);
      SmallVec qa(m);
      for (int a = 0; a < m; ++a) {
        qa[a] = -q[idx[a]];
        for (int b = 0; b < m; ++b) Maa(a, b) = M(idx[a], idx[b]);
      }
      const Eigen::PartialPivLU<Small> lu(Maa);
      if (!(lu.rcond() >= 1e-10)) {
        ++e.singular;
        continue;
      }
      const SmallVec za = lu.solve(qa);
      for (int a = 0; a < m; ++a) z[idx[a]] = za[a];
    }
    w.noalias() = M * z;
    w += q;
    double viol = 0.0;  // how far the basic solution is from z ≥ 0, w ≥ 0
    for (int i = 0; i < n; ++i) viol = std::max(viol, (mask & (1ul << i)) ? -z[i] : -w[i]);
    const double scale = 1.0 + z.cwiseAbs().maxCoeff();
    if (viol <= 1e-6 * scale) {
      if (viol <= 1e-9 * scale && accept(Eigen::VectorXd(z.cwiseMax(0.0)))) {
        e.solved = true;
        e.z = z.cwiseMax(0.0);
        e.detail = "enumeration found a solution at basis " + std::to_string(e.bases) + " of 2^" + std::to_string(n);
        return e;
      }
      ++e.borderline;
    }
  }
  e.proves_none = e.singular == 0 && e.borderline == 0;
  if (e.proves_none)
    e.detail = "exhaustive enumeration: all 2^" + std::to_string(n) +
               " principal submatrices of M are nonsingular and no complementary basis is feasible, so no "
               "solution exists";
  else
    e.detail = "enumeration of 2^" + std::to_string(n) + " complementary bases found no solution (" +
               std::to_string(e.singular) + " singular, " + std::to_string(e.borderline) +
               " borderline: no proof)";
  return e;
}

}  // namespace dc::solvers
