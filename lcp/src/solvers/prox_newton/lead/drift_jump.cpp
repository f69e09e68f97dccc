#include "solvers/prox_newton/lead/drift_jump.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dc::solvers::prox {
namespace {

/// Steps until the gap g (> 0) closes at slope s per step; +∞ when it does not close.
double closes(double gap, double slope) {
  return gap > 0 && slope < 0 ? gap / -slope : std::numeric_limits<double>::infinity();
}

}  // namespace

double drift_steps_to_bound(const LcpProblem& p, const Eigen::VectorXd& lambda, const Eigen::VectorXd& d) {
  double s = std::numeric_limits<double>::infinity();
  for (int i = 0; i < p.rows(); ++i) {
    const int n = p.normal_row[static_cast<size_t>(i)];
    if (n < 0) {
      if (std::isfinite(p.lo[i])) s = std::min(s, closes(lambda[i] - p.lo[i], d[i]));
      if (std::isfinite(p.hi[i])) s = std::min(s, closes(p.hi[i] - lambda[i], -d[i]));
      continue;
    }
    // A friction row's bounds ±μ λ_n move with the normal row (λ_n > 0 stays so until the
    // normal row's own bound, counted there).
    if (!(lambda[n] > 0)) continue;
    // A row riding its bound trails it by up to one step's change of the bound (the sweep
    // clamps it at the bound of the normal row's previous value); its slope is round-off, so
    // only gaps wider than a step's movement count.
    const double mu = p.mu[i];
    const double ride = mu * std::abs(d[n]) + std::abs(d[i]);
    const double up = mu * lambda[n] - lambda[i], down = lambda[i] + mu * lambda[n];
    if (up > ride) s = std::min(s, closes(up, mu * d[n] - d[i]));
    if (down > ride) s = std::min(s, closes(down, d[i] + mu * d[n]));
  }
  return s;
}

std::optional<Eigen::VectorXd> drift_jump(const LcpProblem& p, const Eigen::VectorXd& before_last,
                                          const Eigen::VectorXd& last, const Eigen::VectorXd& now, double linearity) {
  const Eigen::VectorXd d = now - last;
  const double size = d.lpNorm<Eigen::Infinity>();
  if (!(size > 0) || !((d - (last - before_last)).lpNorm<Eigen::Infinity>() <= linearity * size)) return std::nullopt;
  constexpr double kMinSteps = 2;  // a bound within two sweeps: the sweeps get there themselves
  const double s = drift_steps_to_bound(p, now, d);
  if (!(s >= kMinSteps) || !std::isfinite(s)) return std::nullopt;
  Eigen::VectorXd jumped = now + s * d;
  project_feasible(p, jumped);
  return jumped;
}

}  // namespace dc::solvers::prox
