#include "solvers/prox_newton/body_newton.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "dc/lcp/newton_sparse.hpp"
#include "solvers/newton_sparse/gmres.hpp"
#include "solvers/prox_newton/body_metric.hpp"
#include "solvers/prox_newton/exact_line_search.hpp"
#include "solvers/prox_newton/stale_pcg.hpp"

namespace dc::solvers::prox {
namespace {

double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

/// GMRES for the coupled direction: restart length, iteration cap and relative tolerance.
constexpr int kKrylovRestart = 20;
constexpr int kKrylovMax = 40;
constexpr double kKrylovTolerance = 1e-6;
/// CG with a kept factor: relative tolerance on the preconditioned residual norm (an inexact
/// Newton direction; the exact line search takes whatever descent it gives).
constexpr double kPcgTolerance = 1e-6;

}  // namespace

void BodyNewton::bind(const LcpProblem& p) {
  p_ = &p;
  bind_body_metric(p, Jt_, w_, winv_, Winv_diag_, max_diag_);
  normal_.bind(p.J, Jt_);
  all_free_.assign(static_cast<size_t>(w_.size()), 1);
  friction_.clear();
  other_.clear();
  for (int i = 0; i < p.rows(); ++i) (p.is_friction_row(i) ? friction_ : other_).push_back(i);
  factored_mask_.resize(0);  // a new J: the kept factor is of another H
}

double BodyNewton::evaluate(const FrozenSubproblem& sub, Point& pt) {
  const LcpProblem& p = *p_;
  pt.y.noalias() = p.J * pt.v;
  pt.y += sub.c;
  const int n = p.rows();
  pt.lambda.resize(n);
  pt.dmask.resize(n);
  pt.coupling.setZero(n);
  pt.lo = sub.lo;
  pt.hi = sub.hi;
  const double inv = 1.0 / sub.delta;
  const auto row = [&](int i) {
    const double m = -pt.y[i] * inv;
    const bool quadratic = m > pt.lo[i] && m < pt.hi[i];
    pt.dmask[i] = quadratic ? inv : 0.0;
    pt.lambda[i] = quadratic ? m : (m <= pt.lo[i] ? pt.lo[i] : pt.hi[i]);
  };
  if (!sub.coupled) {
    for (int i = 0; i < n; ++i) row(i);
  } else {
    for (const int i : other_) row(i);
    for (const int i : friction_) {  // bounds from the normal row's λ of this same iterate
      const int nr = p.normal_row[static_cast<size_t>(i)];
      const double s = p.mu[i] * std::max(0.0, pt.lambda[nr]);
      pt.lo[i] = -s;
      pt.hi[i] = s;
      row(i);
      // On a bound ±s with an interior normal row: λ_t = ±μ(−y_n/δ), so −∂λ_t/∂y_n = ±μ/δ.
      if (pt.dmask[i] == 0.0 && pt.dmask[nr] > 0.0 && s > 0.0)
        pt.coupling[i] = (pt.lambda[i] > 0 ? 1.0 : -1.0) * p.mu[i] * inv;
    }
  }
  // The dual residual at λ(y): w̃ = J W Jᵀ λ + δλ + c, from λ alone (v enters only through λ).
  pt.Jtl.noalias() = Jt_ * pt.lambda;
  u_ = w_.cwiseProduct(pt.Jtl);
  wt_.noalias() = p.J * u_;
  wt_ += sub.delta * pt.lambda + sub.c;
  double r = 0.0;  // against this iterate's own bounds
  for (int i = 0; i < n; ++i) {
    const double d = std::abs(pt.lambda[i] - std::clamp(pt.lambda[i] - wt_[i], pt.lo[i], pt.hi[i]));
    if (!(d <= r)) r = std::isnan(d) ? INFINITY : d;
  }
  pt.residual = r;
  pt.g = winv_.cwiseProduct(pt.v) - pt.Jtl;  // F = ∇f = W⁻¹ v − Jᵀ λ(y) [N·s]
  double merit = 0.0;
  for (Eigen::Index j = 0; j < pt.g.size(); ++j) merit += w_[j] * pt.g[j] * pt.g[j];
  pt.merit = std::isfinite(merit) ? merit : INFINITY;
  return r;
}

bool BodyNewton::factorize(const Point& pt, double delta, NewtonSparseStats& st) {
  if (factored_mask_.size() == pt.dmask.size() && factored_delta_ == delta && factored_mask_ == pt.dmask) return true;
  normal_.assemble(p_->J, winv_, pt.dmask);  // pattern of JᵀJ whatever D is: the analysis is reused
  factor_.bind(normal_.matrix(), true);
  factored_mask_.resize(0);
  if (!factor_.factorize(all_free_, 0.0, st)) return false;
  factored_mask_ = pt.dmask;
  factored_delta_ = delta;
  return true;
}

void BodyNewton::multiply(const Point& pt, const Eigen::VectorXd& x, Eigen::VectorXd& hx, bool coupled) {
  const LcpProblem& p = *p_;
  jx_.noalias() = p.J * x;
  kx_ = pt.dmask.cwiseProduct(jx_);
  if (coupled)
    for (const int t : friction_)
      if (pt.coupling[t] != 0.0) kx_[t] += pt.coupling[t] * jx_[p.normal_row[static_cast<size_t>(t)]];
  hx.noalias() = Jt_ * kx_;
  hx += winv_.cwiseProduct(x);
}

bool BodyNewton::newton_direction(const FrozenSubproblem& sub, const Point& pt, SubproblemOutcome& out,
                                  NewtonSparseStats& st) {
  const bool kept = factored_mask_.size() == pt.dmask.size();
  const bool current = kept && factored_delta_ == sub.delta && factored_mask_ == pt.dmask;
  // A kept factor of another δ preconditions too: H_new and H_old then differ by D's ratio on
  // the quadratic rows (P⁻¹H's condition number at most that ratio), and CG's cap decides.
  if (!current && kept && sub.stale_factor_iterations > 0) {
    const LinearMap H = [&](const Eigen::VectorXd& x, Eigen::VectorXd& hx) { multiply(pt, x, hx, false); };
    const LinearMap P = [&](const Eigen::VectorXd& r, Eigen::VectorXd& x) { factor_.solve(r, x); };
    const PcgOutcome po = pcg(H, P, -g_, d_, sub.stale_factor_iterations, kPcgTolerance);
    out.cg_iterations += po.iterations;
    if (po.converged && d_.allFinite()) return true;
  }
  if (!factorize(pt, sub.delta, st)) return false;
  factor_.solve(-g_, d_);  // H's own direction: descent for the frozen cost (H SPD)
  return d_.allFinite();
}

bool BodyNewton::direction(const FrozenSubproblem& sub, const Point& pt, SubproblemOutcome& out, bool& coupled_step) {
  coupled_step = false;
  if (!sub.coupled || pt.coupling.isZero(0.0)) return true;
  const LinearMap K = [&](const Eigen::VectorXd& x, Eigen::VectorXd& kx) { multiply(pt, x, kx, true); };
  const LinearMap P = [&](const Eigen::VectorXd& r, Eigen::VectorXd& x) { factor_.solve(r, x); };
  Eigen::VectorXd d;
  const KrylovOutcome ko = gmres(K, P, -g_, d, kKrylovRestart, kKrylovMax, kKrylovTolerance);
  out.krylov_iterations += ko.iterations;
  if (!d.allFinite() || !(dot(d, g_) < 0.0)) return true;  // keep H's direction
  d_ = std::move(d);
  coupled_step = true;
  return true;
}

SubproblemOutcome BodyNewton::solve(const FrozenSubproblem& sub, Eigen::VectorXd& lambda) {
  SubproblemOutcome out;
  NewtonSparseStats st;
  cur_.v = w_.cwiseProduct(Jt_ * lambda);
  evaluate(sub, cur_);
  while (true) {
    if (cur_.residual <= sub.tolerance) {
      out.converged = true;
      break;
    }
    if (out.iterations >= sub.max_iterations || !std::isfinite(cur_.residual)) break;
    ++out.iterations;
    g_ = cur_.g;
    bool coupled_step = false;
    if (!newton_direction(sub, cur_, out, st) || !direction(sub, cur_, out, coupled_step)) {
      out.failed = true;
      break;
    }
    if (sub.coupled && step_on_merit(sub, out)) continue;
    // The exact line search on the cost with the current iterate's bounds frozen.
    e_.noalias() = p_->J * d_;
    LineSearchInput in{&cur_.y, &e_, &cur_.lo, &cur_.hi, sub.delta, dot(d_, winv_.cwiseProduct(cur_.v)),
                       dot(d_, winv_.cwiseProduct(d_))};
    const LineSearchResult ls = exact_line_search(in);
    out.line_search_steps += ls.steps;
    if (!(ls.t > 0.0)) {
      out.failed = true;  // no descent left at round-off level
      break;
    }
    cur_.v += ls.t * d_;
    evaluate(sub, cur_);
  }
  lambda = cur_.lambda;
  out.factorizations = st.factorizations;
  out.analyses = st.analyses;
  return out;
}

bool BodyNewton::step_on_merit(const FrozenSubproblem& sub, SubproblemOutcome& out) {
  // Armijo backtracking on ½ FᵀWF: along a Newton direction its slope at t = 0 is −FᵀWF.
  constexpr double kArmijo = 1e-4;
  constexpr int kTrials = 12;
  double t = 1.0;
  for (int k = 0; k < kTrials; ++k, t *= 0.5) {
    trial_.v = cur_.v + t * d_;
    evaluate(sub, trial_);
    ++out.line_search_steps;
    if (trial_.merit <= (1.0 - 2.0 * kArmijo * t) * cur_.merit) {
      std::swap(cur_, trial_);
      if (k == 0) ++out.full_steps;
      return true;
    }
  }
  return false;
}

}  // namespace dc::solvers::prox
