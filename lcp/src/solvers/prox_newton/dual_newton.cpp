#include "solvers/prox_newton/dual_newton.hpp"

#include <algorithm>
#include <cmath>

namespace dc::solvers::prox {

void DualNewton::bind(const SparseRowMatrix& A) {
  const Eigen::Index n = A.rows();
  SparseRowMatrix I(n, n);
  I.setIdentity();
  // A + 0·I: every diagonal entry stored, so δ is written in place and the pattern never changes.
  frozen_.A = A + 0.0 * I;
  frozen_.A.makeCompressed();
  diag_.assign(static_cast<size_t>(n), -1);
  a_diag_.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index begin = frozen_.A.outerIndexPtr()[i], end = frozen_.A.outerIndexPtr()[i + 1];
    for (Eigen::Index k = begin; k < end; ++k)
      if (frozen_.A.innerIndexPtr()[k] == i) diag_[static_cast<size_t>(i)] = k;
    a_diag_[i] = frozen_.A.valuePtr()[diag_[static_cast<size_t>(i)]];
  }
  frozen_.normal_row.assign(static_cast<size_t>(n), -1);  // fixed bounds: no friction coupling
  frozen_.mu = Eigen::VectorXd::Zero(n);
  delta_ = 0.0;
}

SubproblemOutcome DualNewton::solve(const FrozenSubproblem& sub, Eigen::VectorXd& lambda) {
  SubproblemOutcome out;
  const Eigen::Index n = lambda.size();
  if (sub.delta != delta_) {
    for (Eigen::Index i = 0; i < n; ++i) frozen_.A.valuePtr()[diag_[static_cast<size_t>(i)]] = a_diag_[i] + sub.delta;
    delta_ = sub.delta;
  }
  frozen_.b = sub.c;
  frozen_.lo = sub.lo;
  frozen_.hi = sub.hi;
  for (Eigen::Index i = 0; i < n; ++i) lambda[i] = std::clamp(lambda[i], sub.lo[i], sub.hi[i]);
  SolverOptions so;
  so.max_sweeps = sub.max_iterations;
  so.tolerance = sub.tolerance;
  so.record_theta = false;
  const SolveResult r = newton_.solve(frozen_, lambda, so);
  const NewtonSparseStats st = newton_.last_stats();
  out.iterations = st.iterations;
  out.factorizations = st.factorizations;
  out.analyses = st.analyses;
  out.line_search_steps = st.line_search_trials;
  if (r.lambda.size() == n && r.lambda.allFinite()) lambda = r.lambda;
  out.converged = r.residual <= sub.tolerance;
  out.failed = r.status == SolveStatus::InvalidInput || !lambda.allFinite();
  return out;
}

}  // namespace dc::solvers::prox
