#include "solvers/prox_newton/frozen_subproblem.hpp"

#include <algorithm>
#include <cmath>

namespace dc::solvers::prox {

void freeze(const LcpProblem& p, const Eigen::VectorXd& centre, double delta, FrozenSubproblem& sub) {
  const int n = p.rows();
  sub.lo.resize(n);
  sub.hi.resize(n);
  for (int i = 0; i < n; ++i) {
    sub.lo[i] = p.lower(i, centre);  // friction rows: −μ max(0, λ_n^k), frozen for the pass
    sub.hi[i] = p.upper(i, centre);
  }
  sub.centre = centre;
  sub.delta = delta;
  sub.c = p.b - delta * centre;
}

double subproblem_residual(const FrozenSubproblem& sub, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w) {
  double r = 0.0;
  for (Eigen::Index i = 0; i < lambda.size(); ++i) {
    const double d = std::abs(lambda[i] - std::clamp(lambda[i] - w[i], sub.lo[i], sub.hi[i]));
    if (!(d <= r)) r = std::isnan(d) ? INFINITY : d;
  }
  return r;
}

std::vector<char> hard_modes(const LcpProblem& p, const Eigen::VectorXd& lambda) {
  const Eigen::VectorXd w = lcp_velocity(p, lambda);
  std::vector<char> modes(static_cast<size_t>(p.rows()));
  for (int i = 0; i < p.rows(); ++i) {
    const double y = lambda[i] - w[i];
    modes[static_cast<size_t>(i)] = y <= p.lower(i, lambda) ? 0 : (y >= p.upper(i, lambda) ? 2 : 1);
  }
  return modes;
}

}  // namespace dc::solvers::prox
