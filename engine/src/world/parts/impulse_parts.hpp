#pragma once
// The contact impulse of integration (integrate_bodies), with the bodies' update fused into it.
#include <Eigen/Core>

#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// A non-owning reference to a callable `void(int c0, int c1)` (it must outlive the call).
class ColumnsDone {
 public:
  template <class F>
  ColumnsDone(F& f) noexcept  // NOLINT(google-explicit-constructor): passed as a lambda
      : object_(static_cast<void*>(&f)), call_([](void* o, int c0, int c1) { (*static_cast<F*>(o))(c0, c1); }) {}
  void operator()(int c0, int c1) const { call_(object_, c0, c1); }

 private:
  void* object_;
  void (*call_)(void*, int, int);
};

/// impulse ← Δt · Jᵀλ [N·s] as Eigen evaluates `J.transpose() * lambda * dt` (each dof's sum
/// accumulated from 0 in row order, then multiplied by Δt: the same numbers), then done(0,
/// J.cols()). On the calling thread: a split by blocks of columns, which keeps every sum's order,
/// has each thread read every row that reaches its block, and those reads cost more than the
/// serial product's scatter.
void contact_impulse(const SparseRowMatrix& J, const Eigen::Ref<const Eigen::VectorXd>& lambda, double dt, Eigen::VectorXd& impulse,
                     ColumnsDone done);

}  // namespace dc
