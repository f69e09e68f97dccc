#include "solvers/prox_newton/warm_pivot.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "solvers/exact/lemke_pivoting.hpp"

namespace dc::solvers::prox {

std::vector<int> warm_basis(const SplitLcp& sp, const LcpProblem& p, const Eigen::VectorXd& lambda) {
  const int n = p.rows();
  const double s = sp.c / sp.a;
  const Eigen::VectorXd u = p.A * lambda + Eigen::VectorXd(p.b);  // row velocities [m/s]
  std::vector<int> basic;
  for (int i = 0; i < n; ++i) {
    const int r = sp.at[static_cast<size_t>(i)];
    if (!p.is_friction_row(i)) {
      if (std::max(0.0, lambda[i]) / s > u[i] / sp.c) basic.push_back(r);
      continue;
    }
    const double ln = std::max(0.0, lambda[p.normal_row[static_cast<size_t>(i)]]);
    const double lt = lambda[i], bound = p.mu[i] * ln;
    const bool open = !(ln / s > u[p.normal_row[static_cast<size_t>(i)]] / sp.c);
    const bool sliding = open || std::abs(lt) >= bound * (1 - 1e-9);
    // λ⁺ or λ⁻: the sign of λ_t, or against the slip where λ_t = 0 (an open contact's
    // degenerate zero keeps the slip row's basis nonsingular).
    const bool minus = lt < 0 || (lt == 0 && sliding && u[i] > 0);
    basic.push_back(minus ? r + 1 : r);
    if (sliding && (lt != 0 || u[i] != 0)) basic.push_back(r + 2);  // β = |u_t|
  }
  std::sort(basic.begin(), basic.end());
  return basic;
}

namespace {

/// S reduced to unknowns whose principal block M_SS is nonsingular: on a pile with more closed
/// contacts than velocity unknowns the iterate holds more λ's basic than A has rank. The
/// columns FullPivLU takes as pivots (rank-revealing) are independent; for A's PSD part
/// (J_S W J_Sᵀ) independent columns of A_SS give a nonsingular principal block. The unknowns
/// dropped become nonbasic (their complements basic: Lemke repairs the values).
void independent(const Eigen::MatrixXd& M, std::vector<int>& S) {
  for (int round = 0; round < 3 && !S.empty(); ++round) {
    const Eigen::MatrixXd Mss = M(S, S);
    if (Eigen::PartialPivLU<Eigen::MatrixXd>(Mss).rcond() > 1e-12) return;
    Eigen::FullPivLU<Eigen::MatrixXd> lu(Mss);
    lu.setThreshold(1e-10);
    const int rank = static_cast<int>(lu.rank());
    std::vector<int> kept;
    for (int k = 0; k < rank; ++k) kept.push_back(S[static_cast<size_t>(lu.permutationQ().indices()[k])]);
    std::sort(kept.begin(), kept.end());
    S = std::move(kept);
  }
}

}  // namespace

PivotOutcome warm_pivot_solve(const LcpProblem& p, const Eigen::VectorXd& lambda, int cap) {
  PivotOutcome out;
  auto sp = split_lcp(p, out.why);
  if (!sp) return out;
  if (sp->M.size() == 0) {  // b = 0: λ = 0 solves
    out.lambda = Eigen::VectorXd::Zero(p.rows());
    return out;
  }
  const int N = static_cast<int>(sp->q.size());
  std::vector<int> S = warm_basis(*sp, p, lambda);
  independent(sp->M, S);
  std::vector<int> F;
  std::vector<char> in_s(static_cast<size_t>(N), 0);
  for (const int j : S) in_s[static_cast<size_t>(j)] = 1;
  for (int j = 0; j < N; ++j)
    if (!in_s[static_cast<size_t>(j)]) F.push_back(j);
  const Eigen::MatrixXd& M = sp->M;
  const Eigen::VectorXd& q = sp->q;
  // Basis: z_S and w_F. From w − M z − d z₀ = q, with K = M_SS⁻¹ and G = M_FS K, the rows read
  //   z_S − K w_S + K M_SF z_F − z₀ = −K q_S
  //   w_F − G w_S + (G M_SF − M_FF) z_F − z₀ = q_F − G q_S
  // (d_S = −M_SS 1, d_F = 1 − M_FS 1: the z₀ column is −1 in every row).
  const int cols = 2 * N + 2, z0col = 2 * N, rhs = 2 * N + 1;
  LemkeTableau T = LemkeTableau::Zero(N, cols);
  std::vector<int> basis(static_cast<size_t>(N));
  const int ns = static_cast<int>(S.size()), nf = static_cast<int>(F.size());
  Eigen::MatrixXd K, KMsf, G, GMsf;
  Eigen::VectorXd Kq, Gq;
  if (ns > 0) {
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(M(S, S));
    if (!(lu.rcond() > 1e-14)) {
      out.why = "the iterate's basis matrix is singular";
      return out;
    }
    K = lu.inverse();
    KMsf = K * M(S, F);
    Kq = K * q(S);
    G = M(F, S) * K;
    GMsf = G * M(S, F);
    Gq = G * q(S);
  }
  for (int a = 0; a < ns; ++a) {
    const int i = S[static_cast<size_t>(a)];
    basis[static_cast<size_t>(i)] = N + i;
    for (int b = 0; b < ns; ++b) T(i, S[static_cast<size_t>(b)]) = -K(a, b);
    T(i, N + i) = 1.0;
    for (int b = 0; b < nf; ++b) T(i, N + F[static_cast<size_t>(b)]) = KMsf(a, b);
    T(i, rhs) = -Kq[a];
  }
  for (int a = 0; a < nf; ++a) {
    const int i = F[static_cast<size_t>(a)];
    basis[static_cast<size_t>(i)] = i;
    T(i, i) = 1.0;
    for (int b = 0; b < ns; ++b) T(i, S[static_cast<size_t>(b)]) = -G(a, b);
    for (int b = 0; b < nf; ++b) {
      const int j = F[static_cast<size_t>(b)];
      T(i, N + j) = (ns > 0 ? GMsf(a, b) : 0.0) - M(i, j);
    }
    T(i, rhs) = q[i] - (ns > 0 ? Gq[a] : 0.0);
  }
  T.col(z0col).setConstant(-1.0);
  const LemkePivoting lp = lemke_pivoting_from(std::move(T), std::move(basis), cap);
  out.pivots = lp.pivots;
  out.why = lp.why;
  if (lp.outcome != LemkePivoting::Outcome::Solved) return out;
  Eigen::VectorXd result = sp->lambda(p, lp.z);
  if (result.allFinite()) out.lambda = std::move(result);
  return out;
}

}  // namespace dc::solvers::prox
