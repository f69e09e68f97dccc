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
/// accumulated from 0 in row order, then multiplied by Δt: the same numbers), then done(c0, c1)
/// on ranges of whole bodies' columns covering [0, J.cols()) once each range is final.
///
/// On `threads` > 1 threads (a compressed J on enough bodies), by jobs of bodies: job j owns
/// the bodies [k_j, k_{j+1}) and the rows whose first column is theirs, a block [s_j, s_{j+1})
/// when the rows come sorted by their first column after a leading segment [0, W) of short rows
/// (an assembled step: wall contacts first, then pairs sorted by body a < body b). The terms of
/// a dof of job j then come from, in row order: the leading rows, the rows of earlier blocks
/// that reach beyond their own bodies (each job lists these in a first run), and its own block.
/// Job j adds exactly those, in that order, and calls done() on its columns; the sums are the
/// serial ones bit for bit on every split. A block holding a row outside its bodies (rows not
/// so sorted) is found by the first run, and the product then runs serially; unless `split` is
/// Always, so it does when a sample of the rows finds many reaching later jobs (bodies not
/// numbered in space: the split would cost about what it spreads) or when the calling thread
/// ran every job of the first run (no helper came).
enum class ImpulseSplit { WhenHelped, Always };
void contact_impulse(const SparseRowMatrix& J, const Eigen::Ref<const Eigen::VectorXd>& lambda, double dt, Eigen::VectorXd& impulse,
                     ColumnsDone done, int threads = 1, ImpulseSplit split = ImpulseSplit::WhenHelped);

}  // namespace dc
