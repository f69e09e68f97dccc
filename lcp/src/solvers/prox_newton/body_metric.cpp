#include "solvers/prox_newton/body_metric.hpp"

#include <algorithm>

namespace dc {

void bind_body_metric(const LcpProblem& p, SparseRowMatrix& Jt, Eigen::VectorXd& w, Eigen::VectorXd& winv,
                      SparseRowMatrix& Winv_diag, double& max_diag) {
  Jt = SparseRowMatrix(p.J.transpose());
  w = p.dt * p.inv_mass;
  const Eigen::Index m = w.size();
  winv.resize(m);
  for (Eigen::Index j = 0; j < m; ++j) winv[j] = w[j] > 0 ? 1.0 / w[j] : 1e300;
  Winv_diag.resize(m, m);
  Winv_diag.setIdentity();
  Winv_diag.diagonal() = winv;
  max_diag = 0.0;
  for (int i = 0; i < p.J.rows(); ++i) {
    double a = 0.0;
    for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) a += it.value() * it.value() * w[it.col()];
    max_diag = std::max(max_diag, a);
  }
}

}  // namespace dc
