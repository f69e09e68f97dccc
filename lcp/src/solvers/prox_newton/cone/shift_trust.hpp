#pragma once
// The trust region of prox-newton's following exact-cone passes (cone_passes.hpp): a following
// pass lets de Saxcé's shift ŝ_n = μ|w_t| follow the Newton iterate, which converges
// superlinearly near a solution but may not converge far from it. Its shift is kept within
//     |ŝ_n(v) − ŝ⁰_n| ≤ ρ = τ · m   [m/s]
// of the pass's starting shift ŝ⁰ (ConeSubproblem::shift_center), m = ‖ŝ^{k} − ŝ^{k−1}‖∞ the
// change of the shift over the last accepted pass (the frozen passes' fixed point lies about
// m·q/(1 − q) away at their linear rate q). τ starts at `radius`; an accepted following pass
// (solved, lower hard residual) that cut the best hard residual at least `fast`-fold multiplies
// τ by `grow`, a rejected one divides it by `grow`, and after `retries` rejections in a row the
// passes go back to frozen shifts (τ back at `radius` for the next switch). radius 0 means no
// trust region: the shift follows unbounded and one rejection goes back to frozen shifts.
#include <Eigen/Core>
#include <cmath>

#include "solvers/prox_newton/cone/cone_newton.hpp"

namespace dc::solvers::prox {

class ShiftTrust {
 public:
  ShiftTrust(double radius, double grow, int retries, double fast)
      : radius_(radius), grow_(grow), retries_(retries), fast_(fast), tau_(radius) {}

  /// The change of the shift over the last accepted pass [m/s].
  void moved(double m) { moved_ = m; }

  /// Sets sub's trust region around the shift ŝ⁰ at the pass's start.
  void bound(const Eigen::VectorXd& shift, ConeSubproblem& sub) const {
    if (radius_ <= 0) {
      sub.shift_center.resize(0);
      return;
    }
    sub.shift_center = shift;
    sub.shift_radius = tau_ * moved_;
  }

  /// After a following pass: whether the next pass follows too.
  bool after_following(bool accepted, double res, double before) {
    if (radius_ <= 0) return accepted;
    if (accepted) {
      rejections_ = 0;
      if (res * fast_ <= before) tau_ = std::min(tau_ * grow_, kMaxTau);
      return true;
    }
    tau_ /= grow_;
    if (++rejections_ <= retries_) return true;
    rejections_ = 0;
    tau_ = radius_;
    return false;
  }

  [[nodiscard]] double tau() const { return tau_; }

 private:
  static constexpr double kMaxTau = 1e12;  // effectively unbounded
  double radius_, grow_;
  int retries_;
  double fast_, tau_;
  double moved_ = 0;
  int rejections_ = 0;
};

}  // namespace dc::solvers::prox
