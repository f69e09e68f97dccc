#include "solvers/prox_newton/cone/cone_newton.hpp"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "dc/lcp/newton_sparse.hpp"
#include "solvers/newton_sparse/gmres.hpp"
#include "solvers/prox_newton/body_metric.hpp"
#include "solvers/prox_newton/exact_line_search.hpp"
#include "solvers/prox_newton/cone/friction_cone.hpp"
#include "solvers/prox_newton/stale_pcg.hpp"

namespace dc::solvers::prox {
namespace {

/// CG with a kept factor: relative tolerance on the preconditioned residual norm (an inexact
/// Newton direction; the exact line search takes whatever descent it gives).
constexpr double kPcgTolerance = 1e-6;
/// GMRES for the coupled (follow_shift) direction: restart length, iteration cap, tolerance.
constexpr int kKrylovRestart = 20;
constexpr int kKrylovMax = 40;
constexpr double kKrylovTolerance = 1e-6;

}  // namespace

bool ConeNewton::bind(const LcpProblem& p) {
  p_ = &p;
  contacts_.clear();
  others_.clear();
  const int n = p.rows();
  std::vector<char> in_cone(static_cast<size_t>(n), 0);
  for (int t = 0; t < n; ++t) {
    if (!p.is_friction_row(t)) continue;
    const int nr = p.normal_row[static_cast<size_t>(t)];
    if (p.is_friction_row(nr) || in_cone[static_cast<size_t>(nr)] || !(p.lo[nr] == 0.0) ||
        !(p.hi[nr] == std::numeric_limits<double>::infinity()))
      return false;
    in_cone[static_cast<size_t>(nr)] = in_cone[static_cast<size_t>(t)] = 1;
    contacts_.push_back({nr, t, p.mu[t]});
  }
  for (int i = 0; i < n; ++i)
    if (!in_cone[static_cast<size_t>(i)]) others_.push_back(i);
  bind_body_metric(p, Jt_, w_, winv_, Winv_diag_, max_diag_);
  all_free_.assign(static_cast<size_t>(w_.size()), 1);
  factored_key_.resize(0);  // a new J: the kept factor is of another H
  factored_delta_ = 0.0;
  return true;
}

double ConeNewton::followed_shift(const ConeSubproblem& sub, const Contact& c, double wt, double& sig) {
  const double s = c.mu * std::abs(wt);
  sig = wt > 0 ? c.mu : (wt < 0 ? -c.mu : 0.0);
  if (sub.shift_center.size() == 0) return s;
  const double centre = sub.shift_center[c.n];
  if (s > centre + sub.shift_radius) {
    sig = 0.0;
    return centre + sub.shift_radius;
  }
  if (s < centre - sub.shift_radius) {
    sig = 0.0;
    return centre - sub.shift_radius;
  }
  return s;
}

void ConeNewton::evaluate(const ConeSubproblem& sub, Point& pt, bool residual) {
  const LcpProblem& p = *p_;
  pt.y.noalias() = p.J * pt.v;
  pt.y += sub.c;
  const int n = p.rows();
  const auto nc = static_cast<Eigen::Index>(contacts_.size());
  pt.lambda.resize(n);
  pt.gnn.resize(nc);
  pt.gnt.resize(nc);
  pt.gtt.resize(nc);
  pt.gs.resize(static_cast<Eigen::Index>(others_.size()));
  pt.sig.setZero(nc);
  const double inv = 1.0 / sub.delta;
  for (Eigen::Index k = 0; k < nc; ++k) {
    const Contact& c = contacts_[static_cast<size_t>(k)];
    if (sub.follow_shift) {  // ŝ_n = μ|w_t|, w_t = (J v + b)_t = y_t − c_t + b_t
      const double wt = pt.y[c.t] - sub.c[c.t] + p.b[c.t];
      pt.y[c.n] += followed_shift(sub, c, wt, pt.sig[k]);
    }
    const ConePoint cp = project_cone(c.mu, -pt.y[c.n] * inv, -pt.y[c.t] * inv);
    pt.lambda[c.n] = cp.n;
    pt.lambda[c.t] = cp.t;
    cone_jacobian(cp, pt.gnn[k], pt.gnt[k], pt.gtt[k]);
  }
  for (size_t k = 0; k < others_.size(); ++k) {
    const int i = others_[k];
    const double m = -pt.y[i] * inv;
    const bool inside = m > p.lo[i] && m < p.hi[i];
    pt.gs[static_cast<Eigen::Index>(k)] = inside ? 1.0 : 0.0;
    pt.lambda[i] = inside ? m : (m <= p.lo[i] ? p.lo[i] : p.hi[i]);
  }
  pt.Jtl.noalias() = Jt_ * pt.lambda;
  pt.g = winv_.cwiseProduct(pt.v) - pt.Jtl;  // ∇f = W⁻¹ v − Jᵀ λ(y) [N·s]
  // f = ½ vᵀW⁻¹v + Σ (−λᵀy − ½δ‖λ‖²): each ℓ is its max's value at λ(y).
  double f = 0.0;
  for (Eigen::Index j = 0; j < pt.v.size(); ++j)
    if (pt.v[j] != 0.0) f += 0.5 * winv_[j] * pt.v[j] * pt.v[j];
  for (int i = 0; i < n; ++i) f -= pt.lambda[i] * (pt.y[i] + 0.5 * sub.delta * pt.lambda[i]);
  pt.cost = f;
  double merit = 0.0;
  for (Eigen::Index j = 0; j < pt.g.size(); ++j) merit += w_[j] * pt.g[j] * pt.g[j];
  pt.merit = std::isfinite(merit) ? merit : INFINITY;
  if (!residual) return;
  // w̃ = J W Jᵀ λ + δλ + c, from λ alone; the residual against the cone and the boxes.
  u_ = w_.cwiseProduct(pt.Jtl);
  wt_.noalias() = p.J * u_;  // A λ
  if (sub.follow_shift) {
    double sig = 0;
    for (const Contact& c : contacts_) wt_[c.n] += followed_shift(sub, c, wt_[c.t] + p.b[c.t], sig);
  }
  wt_ += sub.delta * pt.lambda + sub.c;
  double r = 0.0;
  const auto keep = [&r](double d) {
    if (!(d <= r)) r = std::isnan(d) ? INFINITY : d;
  };
  for (const Contact& c : contacts_) {
    const ConePoint cp = project_cone(c.mu, pt.lambda[c.n] - wt_[c.n], pt.lambda[c.t] - wt_[c.t]);
    keep(std::abs(pt.lambda[c.n] - cp.n));
    keep(std::abs(pt.lambda[c.t] - cp.t));
  }
  for (const int i : others_) keep(std::abs(pt.lambda[i] - std::clamp(pt.lambda[i] - wt_[i], p.lo[i], p.hi[i])));
  pt.residual = r;
}

void ConeNewton::multiply(const Point& pt, double delta, const Eigen::VectorXd& x, Eigen::VectorXd& hx,
                          bool coupled) {
  jx_.noalias() = p_->J * x;
  kx_.resize(jx_.size());
  const double inv = 1.0 / delta;
  for (size_t k = 0; k < contacts_.size(); ++k) {
    const Contact& c = contacts_[k];
    const auto kk = static_cast<Eigen::Index>(k);
    const double xt = jx_[c.t], xn = jx_[c.n] + (coupled ? pt.sig[kk] * xt : 0.0);
    kx_[c.n] = inv * (pt.gnn[kk] * xn + pt.gnt[kk] * xt);
    kx_[c.t] = inv * (pt.gnt[kk] * xn + pt.gtt[kk] * xt);
  }
  for (size_t k = 0; k < others_.size(); ++k) {
    const int i = others_[k];
    kx_[i] = inv * pt.gs[static_cast<Eigen::Index>(k)] * jx_[i];
  }
  hx.noalias() = Jt_ * kx_;
  hx += winv_.cwiseProduct(x);
}

void ConeNewton::g_key(const Point& pt, Eigen::VectorXd& key) {
  key.resize(pt.gnn.size() * 3 + pt.gs.size());
  key << pt.gnn, pt.gnt, pt.gtt, pt.gs;
}

bool ConeNewton::factorize(const Point& pt, double delta, NewtonSparseStats& st) {
  g_key(pt, key_);
  if (factored_key_.size() == key_.size() && factored_delta_ == delta && factored_key_ == key_) return true;
  const LcpProblem& p = *p_;
  const double inv = 1.0 / delta;
  // G with every 2×2 block stored whatever its values: H keeps the pattern of JᵀJ and the
  // analysis is reused.
  std::vector<Eigen::Triplet<double>> trips;
  trips.reserve(contacts_.size() * 4 + others_.size());
  for (size_t k = 0; k < contacts_.size(); ++k) {
    const Contact& c = contacts_[k];
    const auto kk = static_cast<Eigen::Index>(k);
    trips.emplace_back(c.n, c.n, inv * pt.gnn[kk]);
    trips.emplace_back(c.n, c.t, inv * pt.gnt[kk]);
    trips.emplace_back(c.t, c.n, inv * pt.gnt[kk]);
    trips.emplace_back(c.t, c.t, inv * pt.gtt[kk]);
  }
  for (size_t k = 0; k < others_.size(); ++k)
    trips.emplace_back(others_[k], others_[k], inv * pt.gs[static_cast<Eigen::Index>(k)]);
  SparseRowMatrix G(p.rows(), p.rows());
  G.setFromTriplets(trips.begin(), trips.end());
  const SparseRowMatrix GJ = G * p.J;
  H_ = Jt_ * GJ;
  H_ += Winv_diag_;
  H_.makeCompressed();
  factor_.bind(H_, true);
  factored_key_.resize(0);
  factored_delta_ = 0.0;
  if (!factor_.factorize(all_free_, 0.0, st)) return false;
  factored_key_ = key_;
  factored_delta_ = delta;
  return true;
}

bool ConeNewton::newton_direction(const ConeSubproblem& sub, const Point& pt, SubproblemOutcome& out,
                                  NewtonSparseStats& st) {
  if (factored_delta_ > 0 && sub.stale_factor_iterations > 0) {
    g_key(pt, key_);
    const bool current = factored_delta_ == sub.delta && factored_key_ == key_;
    if (!current && factored_key_.size() == key_.size()) {
      const LinearMap H = [&](const Eigen::VectorXd& x, Eigen::VectorXd& hx) { multiply(pt, sub.delta, x, hx); };
      const LinearMap P = [&](const Eigen::VectorXd& r, Eigen::VectorXd& x) { factor_.solve(r, x); };
      const PcgOutcome po = pcg(H, P, -g_, d_, sub.stale_factor_iterations, kPcgTolerance);
      out.cg_iterations += po.iterations;
      if (po.converged && d_.allFinite()) return true;
    }
  }
  if (!factorize(pt, sub.delta, st)) return false;
  factor_.solve(-g_, d_);
  return d_.allFinite();
}

void ConeNewton::slope(double delta, double a, double q, double t, double& s, double& curvature) const {
  const Point& pt = cur_;
  const LcpProblem& p = *p_;
  const double inv = 1.0 / delta;
  s = a + t * q;
  double c = q;
  for (const Contact& k : contacts_) {
    const double en = e_[k.n], et = e_[k.t];
    if (en == 0.0 && et == 0.0) continue;
    const ConePoint cp = project_cone(k.mu, -(pt.y[k.n] + t * en) * inv, -(pt.y[k.t] + t * et) * inv);
    s -= en * cp.n + et * cp.t;
    double nn = 0, nt = 0, tt = 0;
    cone_jacobian(cp, nn, nt, tt);
    c += inv * (nn * en * en + 2 * nt * en * et + tt * et * et);
  }
  for (const int i : others_) {
    const double e = e_[i];
    if (e == 0.0) continue;
    const double m = -(pt.y[i] + t * e) * inv;
    if (m > p.lo[i] && m < p.hi[i]) {
      s -= e * m;
      c += e * e * inv;
    } else {
      s -= e * (m <= p.lo[i] ? p.lo[i] : p.hi[i]);
    }
  }
  curvature = c;
}

SubproblemOutcome ConeNewton::solve(const ConeSubproblem& sub, Eigen::VectorXd& lambda) {
  SubproblemOutcome out;
  NewtonSparseStats st;
  cur_.v = w_.cwiseProduct(Jt_ * lambda);
  evaluate(sub, cur_, true);
  while (true) {
    if (cur_.residual <= sub.tolerance) {
      out.converged = true;
      break;
    }
    if (out.iterations >= sub.max_iterations || !std::isfinite(cur_.residual)) break;
    ++out.iterations;
    g_ = cur_.g;
    if (sub.follow_shift && coupled_direction(sub, cur_, out, st) && step_on_merit(sub, out)) continue;
    if (!newton_direction(sub, cur_, out, st)) {
      out.failed = true;
      break;
    }
    e_.noalias() = p_->J * d_;
    const double a = d_.dot(winv_.cwiseProduct(cur_.v)), q = d_.dot(winv_.cwiseProduct(d_));
    const LineSearchResult ls =
        minimise_along([&](double t, double& s, double& c) { slope(sub.delta, a, q, t, s, c); });
    out.line_search_steps += ls.steps;
    if (!(ls.t > 0.0)) {
      out.failed = true;  // no descent left at round-off level
      break;
    }
    if (ls.t == 1.0) ++out.full_steps;
    cur_.v += ls.t * d_;
    evaluate(sub, cur_, true);
  }
  lambda = cur_.lambda;
  out.factorizations = st.factorizations;
  out.analyses = st.analyses;
  return out;
}

bool ConeNewton::coupled_direction(const ConeSubproblem& sub, const Point& pt, SubproblemOutcome& out,
                                   NewtonSparseStats& st) {
  const LinearMap K = [&](const Eigen::VectorXd& x, Eigen::VectorXd& kx) { multiply(pt, sub.delta, x, kx, true); };
  const LinearMap P = [&](const Eigen::VectorXd& r, Eigen::VectorXd& x) { factor_.solve(r, x); };
  g_key(pt, key_);
  bool current = factored_delta_ == sub.delta && factored_key_ == key_;
  if (!current && (factored_delta_ == 0 || sub.stale_factor_iterations == 0)) {
    if (!factorize(pt, sub.delta, st)) return false;
    current = true;
  }
  KrylovOutcome ko = gmres(K, P, -g_, d_, kKrylovRestart, kKrylovMax, kKrylovTolerance);
  out.krylov_iterations += ko.iterations;
  if (ko.converged && d_.allFinite()) return true;
  if (current || !factorize(pt, sub.delta, st)) return false;
  ko = gmres(K, P, -g_, d_, kKrylovRestart, kKrylovMax, kKrylovTolerance);
  out.krylov_iterations += ko.iterations;
  return ko.converged && d_.allFinite();
}

bool ConeNewton::step_on_merit(const ConeSubproblem& sub, SubproblemOutcome& out) {
  // Armijo backtracking on ½ FᵀWF: along a Newton direction its slope at t = 0 is −FᵀWF.
  constexpr double kArmijo = 1e-4;
  constexpr int kTrials = 12;
  double t = 1.0;
  for (int k = 0; k < kTrials; ++k, t *= 0.5) {
    trial_.v = cur_.v + t * d_;
    evaluate(sub, trial_, true);
    ++out.line_search_steps;
    if (trial_.merit <= (1.0 - 2.0 * kArmijo * t) * cur_.merit) {
      std::swap(cur_, trial_);
      if (k == 0) ++out.full_steps;
      return true;
    }
  }
  return false;
}

double ConeNewton::cost(const ConeSubproblem& sub, const Eigen::VectorXd& v, Eigen::VectorXd* gradient) {
  Point pt;
  pt.v = v;
  evaluate(sub, pt, false);
  if (gradient) *gradient = pt.g;
  return pt.cost;
}

void ConeNewton::hessian_times(const ConeSubproblem& sub, const Eigen::VectorXd& v, const Eigen::VectorXd& x,
                               Eigen::VectorXd& hx) {
  Point pt;
  pt.v = v;
  evaluate(sub, pt, false);
  multiply(pt, sub.delta, x, hx, sub.follow_shift);
}

}  // namespace dc::solvers::prox
