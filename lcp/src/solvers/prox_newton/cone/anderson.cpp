#include "solvers/prox_newton/cone/anderson.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace dc::solvers::prox {

Eigen::VectorXd Anderson::next(const Eigen::VectorXd& x, const Eigen::VectorXd& g) {
  x_.push_back(x);
  g_.push_back(g);
  while (static_cast<int>(x_.size()) > depth_ + 1) {
    x_.pop_front();
    g_.pop_front();
  }
  const int m = static_cast<int>(x_.size()) - 1;
  if (m <= 0) return g;
  const Eigen::Index n = x.size();
  Eigen::MatrixXd dF(n, m), dG(n, m);
  for (int j = 0; j < m; ++j) {
    const auto a = static_cast<size_t>(j), b = static_cast<size_t>(j + 1);
    dG.col(j) = g_[b] - g_[a];
    dF.col(j) = (g_[b] - x_[b]) - (g_[a] - x_[a]);
  }
  const Eigen::VectorXd f = g - x;
  Eigen::MatrixXd N(m, m);
  Eigen::VectorXd r(m);
  for (int i = 0; i < m; ++i) {
    r[i] = dF.col(i).dot(f);
    for (int j = 0; j <= i; ++j) N(i, j) = N(j, i) = dF.col(i).dot(dF.col(j));
  }
  const double reg = 1e-12 * N.trace();
  if (!(reg > 0) || !std::isfinite(reg)) return g;
  N.diagonal().array() += reg;
  const Eigen::VectorXd gamma = N.ldlt().solve(r);
  if (!gamma.allFinite()) return g;
  return g - dG * gamma;
}

}  // namespace dc::solvers::prox
