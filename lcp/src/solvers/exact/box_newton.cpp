#include "solvers/exact/box_newton.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "solvers/solver_common.hpp"

namespace dc::solvers {

bool is_symmetric(const SparseRowMatrix& A) {
  const SparseRowMatrix At = A.transpose();
  return (A - At).norm() <= 1e-12 * A.norm();
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Σ_i a_i b_i left to right. Eigen's dot/squaredNorm sum in SIMD-packet order (2, 4 or 8
/// lanes by -march), which would make the Armijo tests build-dependent (docs/reproducibility.md).
template <class A, class B>
double dot_in_order(const A& a, const B& b) {
  double s = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

class BoxNewton {
 public:
  BoxNewton(const BoxNewtonSystem& s) : s_(s), n_(static_cast<int>(s.c.size())) {
    inv_diag_.assign(static_cast<size_t>(n_), 0.0);
    for (int i = 0; i < n_; ++i) {
      const double d = s.A.coeff(i, i), inv = 1.0 / d;
      if (d > 0 && std::isfinite(inv)) inv_diag_[static_cast<size_t>(i)] = inv;
    }
    pos_.resize(static_cast<size_t>(n_));
  }

  // w = Aλ + c, H; returns ‖H‖∞ (+∞ if not finite).
  double eval(const Eigen::VectorXd& l, Eigen::VectorXd& w, Eigen::VectorXd& h) const {
    w.noalias() = s_.A * l;
    w += s_.c;
    h.resize(n_);
    for (int i = 0; i < n_; ++i) h[i] = l[i] - std::clamp(l[i] - w[i], s_.lo[i], s_.hi[i]);
    const double r = n_ ? h.cwiseAbs().maxCoeff() : 0.0;
    return std::isfinite(r) ? r : kInf;
  }
  // q(λ) = ½λᵀAλ + cᵀλ = λᵀ(½(w − c) + c) with w = Aλ + c.
  double objective(const Eigen::VectorXd& l, const Eigen::VectorXd& w) const {
    return dot_in_order(l, 0.5 * (w - s_.c) + s_.c);
  }

  // One projected Gauss–Seidel sweep with the fixed bounds; returns max |Δλ|.
  double pgs_sweep(Eigen::VectorXd& l) const {
    double theta = 0.0;
    for (int i = 0; i < n_; ++i) {
      double r = s_.c[i];
      for (SparseRowMatrix::InnerIterator e(s_.A, i); e; ++e) r += e.value() * l[e.col()];
      const double inv = inv_diag_[static_cast<size_t>(i)];
      const double old = l[i];
      double x = inv > 0 ? old - r * inv : singular_row_update(old, r, s_.lo[i], s_.hi[i]);
      x = std::clamp(x, s_.lo[i], s_.hi[i]);
      if (std::isfinite(x)) l[i] = x;
      theta = std::max(theta, std::abs(l[i] - old));
    }
    return theta;
  }

  // Min-map Newton direction at λ (w, h evaluated there). False with `why` on failure.
  bool direction(const Eigen::VectorXd& l, const Eigen::VectorXd& w, const Eigen::VectorXd& h,
                 Eigen::VectorXd& delta, std::string& why) {
    free_.clear();
    delta.resize(n_);
    for (int i = 0; i < n_; ++i) {
      const double y = l[i] - w[i];
      if (y <= s_.lo[i] || y >= s_.hi[i]) {
        delta[i] = -h[i];
        pos_[static_cast<size_t>(i)] = -1;
      } else {
        pos_[static_cast<size_t>(i)] = static_cast<int>(free_.size());
        free_.push_back(i);
      }
    }
    const int nf = static_cast<int>(free_.size());
    if (nf == 0) return true;
    trip_.clear();
    Eigen::VectorXd rhs(nf);
    for (int k = 0; k < nf; ++k) {
      const int i = free_[static_cast<size_t>(k)];
      double r = -w[i];
      trip_.emplace_back(k, k, s_.rho);
      for (SparseRowMatrix::InnerIterator e(s_.A, i); e; ++e) {
        const int j = static_cast<int>(e.col());
        const int pj = pos_[static_cast<size_t>(j)];
        if (pj >= 0)
          trip_.emplace_back(k, pj, e.value());
        else
          r -= e.value() * delta[j];
      }
      rhs[k] = r;
    }
    Eigen::SparseMatrix<double> K(nf, nf);
    K.setFromTriplets(trip_.begin(), trip_.end());
    Eigen::VectorXd df;
    if (s_.symmetric) {
      Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(K);
      if (ldlt.info() != Eigen::Success) {
        why = "LDLT factorisation of the free block failed";
        return false;
      }
      df = ldlt.solve(rhs);
    } else {
      K.makeCompressed();
      Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
      lu.analyzePattern(K);
      lu.factorize(K);
      if (lu.info() != Eigen::Success) {
        why = "LU factorisation of the free block failed (singular)";
        return false;
      }
      df = lu.solve(rhs);
    }
    if (!df.allFinite()) {
      why = "Newton step is not finite (singular free block)";
      return false;
    }
    for (int k = 0; k < nf; ++k) delta[free_[static_cast<size_t>(k)]] = df[k];
    return true;
  }

  void project(Eigen::VectorXd& l) const {
    for (int i = 0; i < n_; ++i) l[i] = std::clamp(l[i], s_.lo[i], s_.hi[i]);
  }

  const BoxNewtonSystem& s_;
  int n_;
  std::vector<double> inv_diag_;
  std::vector<int> pos_, free_;
  std::vector<Eigen::Triplet<double>> trip_;
};

}  // namespace

BoxNewtonOutcome box_newton(const BoxNewtonSystem& s, Eigen::VectorXd& lambda, double target, int max_iter,
                            const std::function<void(const Eigen::VectorXd&, double)>& on_step) {
  BoxNewton bn(s);
  const int n = bn.n_;
  BoxNewtonOutcome out;
  bn.project(lambda);
  Eigen::VectorXd w(n), h(n), delta(n), trial(n), wt(n), ht(n), start(n);
  double res = bn.eval(lambda, w, h);
  int failures = 0;
  for (int it = 0;; ++it) {
    out.residual = res;
    if (!std::isfinite(res)) {
      out.stop = BoxNewtonStop::NonFinite;
      out.why = "non-finite residual";
      return out;
    }
    if (res <= target) {
      out.converged = true;
      out.stop = BoxNewtonStop::Converged;
      return out;
    }
    if (it >= max_iter) {
      out.stop = BoxNewtonStop::IterationLimit;
      out.why = "iteration limit";
      return out;
    }
    start = lambda;
    std::string why;
    bool stepped = false;
    if (s.symmetric) {
      // (1) a PGS sweep: monotone in q, moves the active set.
      bn.pgs_sweep(lambda);
      res = bn.eval(lambda, w, h);
      if (res <= target) {
        out.residual = res;
      } else if (bn.direction(lambda, w, h, delta, why)) {
        // (2) Newton along the projection arc, Armijo on q.
        const double q0 = bn.objective(lambda, w);
        for (double alpha = 1.0; alpha > 1e-12; alpha *= 0.5) {
          trial = lambda + alpha * delta;
          bn.project(trial);
          const double rt = bn.eval(trial, wt, ht);
          const double qt = bn.objective(trial, wt);
          const double decrease = dot_in_order(w, trial - lambda);  // ∇q·(λ(α) − λ), w = ∇q
          if (std::isfinite(rt) &&
              (rt <= 0.5 * res || qt <= q0 + 1e-4 * std::min(0.0, decrease) + 1e-15 * std::abs(q0))) {
            lambda.swap(trial);
            w.swap(wt);
            h.swap(ht);
            res = rt;
            stepped = true;
            break;
          }
        }
      }
      if (!stepped) ++failures;  // the PGS sweep still made progress
    } else {
      if (bn.direction(lambda, w, h, delta, why)) {
        const double f = dot_in_order(h, h);
        for (double alpha = 1.0; alpha > 1e-10; alpha *= 0.5) {
          trial = lambda + alpha * delta;
          const double rt = bn.eval(trial, wt, ht);
          if (std::isfinite(rt) && dot_in_order(ht, ht) <= (1.0 - 2e-4 * alpha) * f) {
            lambda.swap(trial);
            w.swap(wt);
            h.swap(ht);
            res = rt;
            stepped = true;
            break;
          }
        }
      }
      if (!stepped) {
        ++failures;
        bn.pgs_sweep(lambda);
        res = bn.eval(lambda, w, h);
      }
    }
    ++out.iterations;
    if (on_step) on_step(lambda, (lambda - start).cwiseAbs().maxCoeff());
    if (failures > std::max(20, max_iter / 2)) {
      out.residual = res;
      out.stop = BoxNewtonStop::NoProgress;
      out.why = why.empty() ? "line search failed repeatedly" : why;
      return out;
    }
  }
}

}  // namespace dc::solvers
