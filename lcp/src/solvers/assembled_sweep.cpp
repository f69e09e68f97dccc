#include "solvers/assembled_sweep.hpp"

#include <cmath>

namespace dc::solvers {

AssembledSweep::AssembledSweep(const LcpProblem& p) : p_(p), bounds_(p) {
  if (p.A.isCompressed()) {
    A_ = &p.A;
  } else {
    compressed_ = p.A;
    compressed_.makeCompressed();
    A_ = &compressed_;
  }
  const int n = p.rows();
  inv_diag_.assign(static_cast<size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    const double d = A_->coeff(i, i);
    const double inv = 1.0 / d;
    if (d > 0 && std::isfinite(inv))
      inv_diag_[static_cast<size_t>(i)] = inv;
    else
      singular_.push_back(i);
  }
}

double AssembledSweep::sweep(Eigen::VectorXd& lambda, double omega, bool& nonfinite) const {
  const int n = p_.rows();
  const int* outer = A_->outerIndexPtr();
  const int* inner = A_->innerIndexPtr();
  const double* val = A_->valuePtr();
  const double* b = p_.b.data();
  double* lam = lambda.data();
  double theta = 0.0;
  bool bad = false;
  for (int i = 0; i < n; ++i) {
    const auto u = static_cast<size_t>(i);
    double r = b[i];
    for (int k = outer[i]; k < outer[i + 1]; ++k) r += val[k] * lam[inner[k]];
    const double old = lam[i];
    const double t = bounds_.mu[u] * std::max(0.0, lam[bounds_.coupled[u]]);
    const double lo = bounds_.lo_fixed[u] - t, hi = bounds_.hi_fixed[u] + t;
    const double inv = inv_diag_[u];
    double x = inv > 0 ? old - omega * r * inv : singular_row_update(old, r, lo, hi);
    x = std::min(std::max(x, lo), hi);  // NaN propagates (x is the first argument)
    bad |= !std::isfinite(x);
    lam[i] = x;
    theta = std::max(theta, std::abs(x - old));
  }
  nonfinite = nonfinite || bad;
  return theta;
}

}  // namespace dc::solvers
