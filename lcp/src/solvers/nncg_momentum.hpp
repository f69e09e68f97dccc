#pragma once
// NNCG's momentum between sweeps (Silcowitz, Niebe, Erleben 2010; Fletcher–Reeves): shared by
// "nncg" (nncg.cpp, on pgs's natural-order sweep) and "nncg-colored" (pgs_colored.cpp, on
// pgs-colored's colour-ordered batches, whose packed λ it moves). It works on flat arrays, λ [N]
// and its Δu image [m/s, rad/s], so the sweep that runs between its calls is its caller's.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "solvers/solver_common.hpp"

namespace dc::solvers {

/// The NNCG state between sweeps: direction p (and its Δu image pu), the sweep's starting point,
/// and the factor of the next move. `velocity_entries` = 0: no Δu
/// (assembled form). Two passes over the rows per iteration besides the sweep: after it, θ and
/// ‖Δf‖²; before the next, the direction update and the move fused in one loop.
class NncgMomentum {
 public:
  NncgMomentum(int rows, int velocity_entries)
      : p_(static_cast<size_t>(rows), 0.0), start_(p_),
        pu_(static_cast<size_t>(velocity_entries), 0.0), start_u_(pu_) {}

  /// Before a sweep: p ← β p + Δf (or 0 after a restart), λ += β p_old (Δu too), and the
  /// sweep's starting point.
  void before_sweep(double* lam, double* du) {
    const double beta = beta_;
    const bool keep = next_ != Next::Restart;
    for (size_t i = 0; i < p_.size(); ++i) {
      const double m = beta * p_[i];
      p_[i] = keep ? m + (lam[i] - start_[i]) : 0.0;
      lam[i] += m;
      start_[i] = lam[i];
    }
    move_velocities(du, beta, keep);
  }

  /// before_sweep for a sweep that reads λ^{k−1} from one array and writes λ^k to another
  /// (pgs-colored's kernels): `lam`, the last sweep's output, stays as it is; the moved point
  /// λ + β p_old, the same values before_sweep leaves in λ, goes to the array returned, the
  /// sweep's input (kept here until after_sweep has read it); Δu moves in place. So the caller
  /// still holds a projecting sweep's output should the next sweep break down.
  [[nodiscard]] const double* before_sweep_from(const double* lam, double* du) {
    const double beta = beta_;
    const bool keep = next_ != Next::Restart;
    for (size_t i = 0; i < p_.size(); ++i) {
      const double m = beta * p_[i];
      p_[i] = keep ? m + (lam[i] - start_[i]) : 0.0;
      start_[i] = lam[i] + m;
    }
    move_velocities(du, beta, keep);
    return start_.data();
  }

  /// After the sweep: θ_k = max_i |Δf_k,i| [N], the sweep's change from its own starting
  /// point (the move excluded), and the factor of the next move, β = ‖Δf_k‖²/‖Δf_{k−1}‖², or a restart when β > 1.
  double after_sweep(const double* lam) {
    // Four partial sums and maxima (rows i ≡ j mod 4), combined in a fixed order: a single
    // running sum would put one add latency per row on a dependency chain, and the order stays
    // the same on every build.
    double th0 = 0, th1 = 0, th2 = 0, th3 = 0, sq0 = 0, sq1 = 0, sq2 = 0, sq3 = 0;
    const size_t n = p_.size();
    auto at = [&](size_t i, double& th, double& sq) {
      const double df = lam[i] - start_[i];
      th = std::max(th, std::abs(df));
      sq += df * df;
    };
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
      at(i, th0, sq0);
      at(i + 1, th1, sq1);
      at(i + 2, th2, sq2);
      at(i + 3, th3, sq3);
    }
    for (; i < n; ++i) at(i, th0, sq0);
    double theta = std::max(std::max(th0, th1), std::max(th2, th3));
    const double norm2 = (sq0 + sq1) + (sq2 + sq3);
    if (!std::isfinite(norm2)) theta = norm2;  // let the driver see the non-finite change
    if (next_ == Next::First) {
      // p_1 = Δf_1 (taken in the next before_sweep with β = 0): no move yet.
      next_ = Next::Momentum;
      beta_ = 0.0;
    } else {
      // A zero previous change (solved exactly) restarts, as in Bullet.
      const double beta = prev_norm2_ > 0 ? norm2 / prev_norm2_ : 2.0;
      if (beta > 1.0) {
        ++restarts_;
        beta_ = 0.0;
        next_ = Next::Restart;
      } else {
        beta_ = beta;
        next_ = Next::Momentum;
      }
    }
    prev_norm2_ = norm2;
    return theta;
  }

  [[nodiscard]] int restarts() const { return restarts_; }

 private:
  /// Δu's share of the move: pu ← β pu + (Δu − its start) (0 after a restart), Δu += β pu_old.
  void move_velocities(double* du, double beta, bool keep) {
    for (size_t i = 0; i < pu_.size(); ++i) {
      const double m = beta * pu_[i];
      pu_[i] = keep ? m + (du[i] - start_u_[i]) : 0.0;
      du[i] += m;
      start_u_[i] = du[i];
    }
  }

  enum class Next { First, Momentum, Restart };
  std::vector<double> p_, start_;  // per row [N]
  std::vector<double> pu_, start_u_;      // per Δu entry [m/s, rad/s]
  double prev_norm2_ = 0.0, beta_ = 0.0;
  Next next_ = Next::First;
  int restarts_ = 0;
};

/// What runs between two double-buffered sweeps (pgs-colored's) besides the driver's
/// bookkeeping: nncg-colored's momentum (null: none, pgs-colored) and the caller's watch.
struct MomentumBetweenSweeps {
  NncgMomentum* momentum = nullptr;
  const SweepWatch* watch = nullptr;

  /// The sweep's input: the last sweep's λ `last`, or with the momentum the moved point
  /// λ + β p (Δu moved with it in place; `last` stays a projecting sweep's output).
  [[nodiscard]] const double* start(const double* last, double* du) const {
    return momentum != nullptr ? momentum->before_sweep_from(last, du) : last;
  }
  /// After the sweep wrote λ^k to `out`: the momentum's next β; false when θ [N] (the kernels'
  /// max |λ^k − start|, the momentum's θ too) or ‖Δf‖² is not finite.
  [[nodiscard]] bool finish(const double* out, double theta) const {
    const bool finite = momentum == nullptr || std::isfinite(momentum->after_sweep(out));
    return finite && std::isfinite(theta);
  }
};

}  // namespace dc::solvers
