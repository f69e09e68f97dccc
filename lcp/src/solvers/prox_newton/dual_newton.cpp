#include "solvers/prox_newton/dual_newton.hpp"

#include <algorithm>
#include <cmath>

namespace dc::solvers::prox {
namespace {

constexpr double kArmijo = 1e-4;
constexpr int kMaxHalvings = 40;

/// Σ_i a_i b_i in index order (no packet-order sums: the same iterates in every build).
double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

void clamp_into(const FrozenSubproblem& sub, Eigen::VectorXd& lambda) {
  for (Eigen::Index i = 0; i < lambda.size(); ++i) lambda[i] = std::clamp(lambda[i], sub.lo[i], sub.hi[i]);
}

}  // namespace

void DualNewton::bind(const SparseRowMatrix& A) {
  A_ = &A;
  factor_.bind(A, true);
  diag_ = A.diagonal();
}

double DualNewton::energy(const FrozenSubproblem& sub, const Eigen::VectorXd& lambda, Eigen::VectorXd& w) const {
  w.noalias() = *A_ * lambda;
  w += sub.delta * lambda + sub.c;
  // E = ½ λᵀ(A + δI)λ + cᵀλ = ½ λᵀ(w̃ + c)
  double e = 0.0;
  for (Eigen::Index i = 0; i < lambda.size(); ++i) e += 0.5 * lambda[i] * (w[i] + sub.c[i]);
  return std::isfinite(e) ? e : INFINITY;
}

SubproblemOutcome DualNewton::solve(const FrozenSubproblem& sub, Eigen::VectorXd& lambda) {
  SubproblemOutcome out;
  const int n = static_cast<int>(lambda.size());
  clamp_into(sub, lambda);
  double e = energy(sub, lambda, w_);
  NewtonSparseStats st;
  while (true) {
    const double res = subproblem_residual(sub, lambda, w_);
    if (res <= sub.tolerance) {
      out.converged = true;
      break;
    }
    if (out.iterations >= sub.max_iterations || !std::isfinite(res)) break;
    ++out.iterations;
    // ε-active rows move onto their bound; the rest take the Newton step given that move.
    free_.assign(static_cast<size_t>(n), 1);
    delta_ = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < n; ++i) {
      const bool at_lo = lambda[i] - sub.lo[i] <= res && w_[i] > 0;
      const bool at_hi = sub.hi[i] - lambda[i] <= res && w_[i] < 0;
      if (!at_lo && !at_hi && sub.lo[i] < sub.hi[i]) continue;
      free_[static_cast<size_t>(i)] = 0;
      const double h = diag_[i] + sub.delta;
      delta_[i] = std::clamp(lambda[i] - w_[i] / h, sub.lo[i], sub.hi[i]) - lambda[i];
    }
    rhs_.noalias() = *A_ * delta_;
    for (int i = 0; i < n; ++i) rhs_[i] = free_[static_cast<size_t>(i)] ? -w_[i] - rhs_[i] : 0.0;
    if (!factor_.factorize(free_, sub.delta, st)) {
      out.failed = true;
      break;
    }
    factor_.solve(rhs_, x_);
    for (int i = 0; i < n; ++i)
      if (free_[static_cast<size_t>(i)]) delta_[i] = x_[i];
    // Projected Armijo search on E.
    bool accepted = false;
    double alpha = 1.0;
    for (int k = 0; k <= kMaxHalvings && !accepted; ++k, alpha *= 0.5) {
      trial_ = lambda + alpha * delta_;
      clamp_into(sub, trial_);
      const double et = energy(sub, trial_, trial_w_);
      ++out.line_search_steps;
      const double slope = dot(w_, trial_ - lambda);  // gᵀ(λ_α − λ), g = w̃
      if (et <= e + kArmijo * std::min(slope, 0.0) && et <= e) {
        lambda.swap(trial_);
        w_.swap(trial_w_);
        e = et;
        accepted = true;
      }
    }
    if (!accepted) {
      out.failed = true;
      break;
    }
  }
  out.factorizations = st.factorizations;
  out.analyses = st.analyses;
  return out;
}

}  // namespace dc::solvers::prox
