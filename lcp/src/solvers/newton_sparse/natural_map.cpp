#include "solvers/newton_sparse/natural_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dc::solvers {

void evaluate_natural_map(const LcpProblem& p, const Eigen::VectorXd& lambda, double scale, NaturalMapValue& out) {
  const int n = p.rows();
  out.w.noalias() = p.A * lambda;
  out.w += p.b;
  out.h.resize(n);
  double mx = 0.0, sq = 0.0;
  for (int i = 0; i < n; ++i) {
    const double v = lambda[i] - std::clamp(lambda[i] - out.w[i], p.lower(i, lambda), p.upper(i, lambda));
    out.h[i] = v;
    mx = std::max(mx, std::abs(v));
    sq += (scale * v) * (scale * v);  // row order: packet-order sums would make the line search build-dependent
  }
  const bool finite = std::isfinite(mx) && out.w.allFinite();
  out.max_abs = finite ? mx : std::numeric_limits<double>::infinity();
  out.merit = finite ? 0.5 * sq : std::numeric_limits<double>::infinity();
}

void project_onto_bounds(const LcpProblem& p, Eigen::VectorXd& lambda) {
  const int n = p.rows();
  for (int i = 0; i < n; ++i)
    if (!p.is_friction_row(i)) lambda[i] = std::clamp(lambda[i], p.lo[i], p.hi[i]);
  for (int i = 0; i < n; ++i)
    if (p.is_friction_row(i)) lambda[i] = std::clamp(lambda[i], p.lower(i, lambda), p.upper(i, lambda));
}

void linearize(const LcpProblem& p, const Eigen::VectorXd& lambda, const NaturalMapValue& value,
               NewtonLinearization& lin) {
  const int n = p.rows();
  lin.free.assign(static_cast<size_t>(n), 0);
  lin.known = Eigen::VectorXd::Zero(n);
  lin.couplings.clear();
  lin.free_count = 0;
  // Fixed-bound (normal) rows first: a clamped friction row reads its normal row's move.
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < n; ++i) {
      const bool friction = p.is_friction_row(i);
      if (friction != (pass == 1)) continue;
      const double y = lambda[i] - value.w[i];
      const double lo = p.lower(i, lambda), hi = p.upper(i, lambda);
      if (y > lo && y < hi) {
        lin.free[static_cast<size_t>(i)] = 1;
        ++lin.free_count;
        continue;
      }
      lin.known[i] = -value.h[i];
      if (!friction) continue;
      const int nr = p.normal_row[static_cast<size_t>(i)];
      if (!(lambda[nr] > 0.0)) continue;  // bound μ max(0, λ_n) is flat in λ_n here
      const double slope = (y >= hi ? 1.0 : -1.0) * p.mu[i];
      if (lin.free[static_cast<size_t>(nr)])
        lin.couplings.push_back({i, nr, slope});
      else
        lin.known[i] += slope * lin.known[nr];
    }
  }
}

}  // namespace dc::solvers
