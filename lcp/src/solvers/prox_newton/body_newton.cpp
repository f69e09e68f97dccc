#include "solvers/prox_newton/body_newton.hpp"

#include <algorithm>
#include <cmath>

#include "dc/lcp/newton_sparse.hpp"
#include "solvers/prox_newton/exact_line_search.hpp"

namespace dc::solvers::prox {
namespace {

double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace

void BodyNewton::bind(const LcpProblem& p) {
  p_ = &p;
  Jt_ = SparseRowMatrix(p.J.transpose());
  w_ = p.dt * p.inv_mass;
  const Eigen::Index m = w_.size();
  winv_.resize(m);
  // A body of infinite mass (M⁻¹ = 0) gets a huge W⁻¹: it does not move, H stays finite.
  for (Eigen::Index j = 0; j < m; ++j) winv_[j] = w_[j] > 0 ? 1.0 / w_[j] : 1e300;
  Winv_diag_.resize(m, m);
  Winv_diag_.setIdentity();
  Winv_diag_.diagonal() = winv_;
  max_diag_ = 0.0;
  for (int i = 0; i < p.J.rows(); ++i) {
    double a = 0.0;
    for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) a += it.value() * it.value() * w_[it.col()];
    max_diag_ = std::max(max_diag_, a);
  }
  all_free_.assign(static_cast<size_t>(m), 1);
}

double BodyNewton::evaluate(const FrozenSubproblem& sub, Eigen::VectorXd& lambda) {
  const LcpProblem& p = *p_;
  y_.noalias() = p.J * v_;
  y_ += sub.c;
  const int n = p.rows();
  dmask_.resize(n);
  const double inv = 1.0 / sub.delta;
  for (int i = 0; i < n; ++i) {
    const double m = -y_[i] * inv;
    const bool quadratic = m > sub.lo[i] && m < sub.hi[i];
    dmask_[i] = quadratic ? inv : 0.0;
    lambda[i] = quadratic ? m : (m <= sub.lo[i] ? sub.lo[i] : sub.hi[i]);
  }
  // The dual residual at λ(y): w̃ = J W Jᵀ λ + δλ + c, from λ alone (v enters only through λ).
  Jtl_.noalias() = Jt_ * lambda;
  u_ = w_.cwiseProduct(Jtl_);
  wt_.noalias() = p.J * u_;
  wt_ += sub.delta * lambda + sub.c;
  return subproblem_residual(sub, lambda, wt_);
}

void BodyNewton::assemble_hessian(double /*delta*/) {
  const SparseRowMatrix DJ = dmask_.asDiagonal() * p_->J;
  H_ = Jt_ * DJ;  // structural pattern of JᵀJ whatever D is: the analysis is reused
  H_ += Winv_diag_;
  H_.makeCompressed();
}

SubproblemOutcome BodyNewton::solve(const FrozenSubproblem& sub, Eigen::VectorXd& lambda) {
  SubproblemOutcome out;
  NewtonSparseStats st;
  v_ = w_.cwiseProduct(Jt_ * lambda);
  double res = evaluate(sub, lambda);
  while (true) {
    if (res <= sub.tolerance) {
      out.converged = true;
      break;
    }
    if (out.iterations >= sub.max_iterations || !std::isfinite(res)) break;
    ++out.iterations;
    g_ = winv_.cwiseProduct(v_) - Jtl_;  // ∇f = W⁻¹ v − Jᵀ λ(y)
    assemble_hessian(sub.delta);
    factor_.bind(H_, true);
    if (!factor_.factorize(all_free_, 0.0, st)) {
      out.failed = true;
      break;
    }
    factor_.solve(-g_, d_);
    if (!d_.allFinite()) {
      out.failed = true;
      break;
    }
    e_.noalias() = p_->J * d_;
    LineSearchInput in{&y_, &e_, &sub.lo, &sub.hi, sub.delta, dot(d_, winv_.cwiseProduct(v_)),
                       dot(d_, winv_.cwiseProduct(d_))};
    const LineSearchResult ls = exact_line_search(in);
    out.line_search_steps += ls.steps;
    if (!(ls.t > 0.0)) {
      out.failed = true;  // no descent left at round-off level
      break;
    }
    v_ += ls.t * d_;
    res = evaluate(sub, lambda);
  }
  out.factorizations = st.factorizations;
  out.analyses = st.analyses;
  return out;
}

}  // namespace dc::solvers::prox
