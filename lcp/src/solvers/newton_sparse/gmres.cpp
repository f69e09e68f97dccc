#include "solvers/newton_sparse/gmres.hpp"

#include <cmath>
#include <utility>
#include <vector>

namespace dc::solvers {

double dot_in_order(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

double dot_in_lanes(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  // One serial chain of adds (dot_in_order) waits an add's latency per element; kDotLanes
  // independent partial sums do not, and the order of every addition is still fixed by the
  // source alone (no reassociation, -ffp-contract=off): the same bits in every build.
  constexpr Eigen::Index kDotLanes = 8;
  const Eigen::Index n = a.size(), whole = n - n % kDotLanes;
  const double* pa = a.data();
  const double* pb = b.data();
  double lane[kDotLanes] = {};
  for (Eigen::Index i = 0; i < whole; i += kDotLanes)
    for (Eigen::Index j = 0; j < kDotLanes; ++j) lane[j] += pa[i + j] * pb[i + j];
  for (Eigen::Index width = kDotLanes / 2; width > 0; width /= 2)
    for (Eigen::Index j = 0; j < width; ++j) lane[j] += lane[j + width];
  double s = lane[0];
  for (Eigen::Index i = whole; i < n; ++i) s += pa[i] * pb[i];
  return s;
}

namespace {

/// The restart cycles from x with r = b − K x (beta = ‖r‖, bnorm = ‖b‖): GMRES on K e = r, x += e.
KrylovOutcome gmres_cycles(const LinearMap& K, const LinearMap& P_inverse, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                           Eigen::VectorXd r, double beta, double bnorm, int restart, int max_iterations,
                           double tolerance, Dot dot) {
  KrylovOutcome out;
  const Eigen::Index n = b.size();
  out.relative_residual = beta / bnorm;
  if (beta <= tolerance * bnorm) {  // the start already meets the tolerance (x = 0 when b = 0)
    out.converged = true;
    return out;
  }
  const int m = std::max(1, restart);
  std::vector<Eigen::VectorXd> V(static_cast<size_t>(m + 1)), Z(static_cast<size_t>(m));
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(m + 1, m);
  Eigen::VectorXd cs(m), sn(m), g(m + 1), w(n);
  double previous_beta = beta;
  while (out.iterations < max_iterations) {
    V[0] = r / beta;
    g.setZero();
    g[0] = beta;
    int k = 0;
    for (; k < m && out.iterations < max_iterations; ++k) {
      P_inverse(V[static_cast<size_t>(k)], Z[static_cast<size_t>(k)]);
      K(Z[static_cast<size_t>(k)], w);
      for (int i = 0; i <= k; ++i) {  // modified Gram–Schmidt
        H(i, k) = dot(w, V[static_cast<size_t>(i)]);
        w -= H(i, k) * V[static_cast<size_t>(i)];
      }
      H(k + 1, k) = std::sqrt(dot(w, w));
      for (int i = 0; i < k; ++i) {  // the Givens rotations of columns < k
        const double t = cs[i] * H(i, k) + sn[i] * H(i + 1, k);
        H(i + 1, k) = -sn[i] * H(i, k) + cs[i] * H(i + 1, k);
        H(i, k) = t;
      }
      const double hk = H(k, k), hk1 = H(k + 1, k), den = std::hypot(hk, hk1);
      cs[k] = den > 0 ? hk / den : 1.0;
      sn[k] = den > 0 ? hk1 / den : 0.0;
      const double lucky = H(k + 1, k);
      H(k, k) = den;
      H(k + 1, k) = 0.0;
      g[k + 1] = -sn[k] * g[k];
      g[k] = cs[k] * g[k];
      ++out.iterations;
      if (lucky > 0.0) V[static_cast<size_t>(k + 1)] = w / lucky;
      if (std::abs(g[k + 1]) <= tolerance * bnorm || !(lucky > 0.0)) {
        ++k;
        break;
      }
    }
    // y = H(0:k, 0:k)⁻¹ g(0:k), back substitution; x += Z y.
    Eigen::VectorXd y(k);
    for (int i = k - 1; i >= 0; --i) {
      double s = g[i];
      for (int j = i + 1; j < k; ++j) s -= H(i, j) * y[j];
      y[i] = H(i, i) != 0.0 ? s / H(i, i) : 0.0;
    }
    for (int i = 0; i < k; ++i) x += y[i] * Z[static_cast<size_t>(i)];
    K(x, w);
    r = b - w;
    beta = std::sqrt(dot(r, r));
    out.relative_residual = beta / bnorm;
    if (!std::isfinite(beta)) break;
    if (beta <= tolerance * bnorm) {
      out.converged = true;
      break;
    }
    if (beta > 0.5 * previous_beta) break;  // a restart cycle that does not halve ‖r‖: round-off floor
    previous_beta = beta;
  }
  return out;
}

}  // namespace

KrylovOutcome gmres(const LinearMap& K, const LinearMap& P_inverse, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                    int restart, int max_iterations, double tolerance, Dot dot) {
  x = Eigen::VectorXd::Zero(b.size());
  const double bnorm = std::sqrt(dot(b, b));
  if (!(bnorm > 0.0) || !std::isfinite(bnorm)) return KrylovOutcome{0, 0.0, bnorm == 0.0};
  return gmres_cycles(K, P_inverse, b, x, b, bnorm, bnorm, restart, max_iterations, tolerance, dot);
}

KrylovOutcome gmres_from(const LinearMap& K, const LinearMap& P_inverse, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                         int restart, int max_iterations, double tolerance, Dot dot) {
  const double bnorm = std::sqrt(dot(b, b));
  if (x.size() != b.size() || !x.allFinite() || !(bnorm > 0.0) || !std::isfinite(bnorm))
    return gmres(K, P_inverse, b, x, restart, max_iterations, tolerance, dot);
  Eigen::VectorXd r(b.size());
  K(x, r);
  r = b - r;
  const double beta = std::sqrt(dot(r, r));
  // A start worse than x = 0 (or not finite through K) is dropped: GMRES from zero then.
  if (!std::isfinite(beta) || beta >= bnorm) return gmres(K, P_inverse, b, x, restart, max_iterations, tolerance, dot);
  return gmres_cycles(K, P_inverse, b, x, std::move(r), beta, bnorm, restart, max_iterations, tolerance, dot);
}

}  // namespace dc::solvers
