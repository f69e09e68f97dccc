#pragma once
// How prox-newton steers a run of proximal passes (the outer loop of prox_newton.cpp): the
// passes of a Newton part, the body-space finish's coupled passes, the lead stage's probe, and
// the rule for δ in the finish's steady runs.
#include <algorithm>
#include <cmath>

#include "dc/lcp/prox_newton.hpp"

namespace dc::solvers::prox {

/// How a run of passes is steered (the outer loop).
struct Passes {
  bool coupled = false;   ///< body space: the hard proximal subproblem (coupled bounds)
  double shift = 0;       ///< first δ relative to max A_ii
  int inner = 0;          ///< Newton iterations per pass at most
  int max_stalls = 1;     ///< passes without a new best before the run stops
  int iterations = 0;     ///< Newton iterations of the run at most
  bool steady_shift = false;  ///< δ by steady_shift instead of shrinking after every solved pass
  bool finish = true;         ///< newton-sparse's short finish once the row modes repeat
};

/// A Newton part's passes (`body`: in body space), for at most `left` Newton iterations.
[[nodiscard]] inline Passes frozen_passes(const ProxNewtonDef& def, bool body, int left) {
  Passes ps;
  ps.coupled = body && def.coupled_bounds;
  ps.shift = def.initial_shift;
  ps.inner = body ? std::min(def.inner_iterations, def.body_inner_iterations) : def.inner_iterations;
  ps.max_stalls = def.max_stalls;
  ps.iterations = left;
  return ps;
}

/// The body-space finish: coupled passes from the best iterate, δ from initial_shift and then
/// by steady_shift, for at most `left` Newton iterations (and body_finish_iterations).
[[nodiscard]] inline Passes coupled_passes(const ProxNewtonDef& def, int left) {
  Passes ps;
  ps.coupled = true;
  ps.shift = def.initial_shift;
  ps.inner = def.inner_iterations;
  ps.max_stalls = 3;
  ps.iterations = std::min(def.body_finish_iterations, left);
  ps.steady_shift = true;
  return ps;
}

/// A probe of the lead stage (ProxNewtonDef::probe_sweeps): coupled passes for at most
/// probe_iterations Newton iterations (and `left`), without newton-sparse's finish.
[[nodiscard]] inline Passes probe_passes(const ProxNewtonDef& def, int left) {
  Passes ps;
  ps.coupled = true;
  ps.shift = def.probe_shift > 0 ? def.probe_shift : def.initial_shift;
  ps.inner = def.inner_iterations;
  ps.max_stalls = def.max_stalls;
  ps.iterations = std::min(def.probe_iterations, left);
  ps.finish = false;
  return ps;
}

/// δ after a coupled pass at δ = shift: kept while solved passes lower the hard residual at
/// least kSteadyRate-fold (the proximal point at fixed δ converges linearly; a smaller δ makes
/// the coupled subproblem as hard as the hard problem itself), shrunk √shrink-fold when they
/// are slower but never to a δ whose pass failed, grown after a failed pass. `res` and `before`
/// are the hard residuals [N] after the pass and the best before it; `failed` the largest δ
/// whose pass failed so far (updated).
[[nodiscard]] inline double steady_shift(const ProxNewtonDef& def, double shift, bool converged, double res,
                                         double before, double& failed) {
  constexpr double kSteadyRate = 4.0;
  if (!converged) {
    failed = std::max(failed, shift);
    return std::min(def.max_shift, shift * def.shrink);
  }
  if (res * kSteadyRate <= before) return shift;
  const double next = std::max(def.min_shift, shift / std::sqrt(def.shrink));
  return next > failed ? next : shift;
}

}  // namespace dc::solvers::prox
