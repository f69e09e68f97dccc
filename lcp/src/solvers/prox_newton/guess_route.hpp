#pragma once
// Settings of prox-newton's proximal finish in the Newton part from the guess after a first
// Newton part from the lead stage's iterate (ProxNewtonDef::guess_route_from_floor,
// guess_fallback_cap_fall, guess_floor_stalls).
#include <algorithm>

#include "dc/lcp/prox_newton.hpp"
#include "dc/lcp/proximal_point.hpp"

namespace dc::solvers::prox {

/// Applies the guess part's settings to `route`; `first_floor` is the failure floor of δ
/// (relative to max_i A_ii) the first part's proximal finish ended with, 0 when it did not run.
inline void apply_guess_route(const ProxNewtonDef& def, double first_floor, ProximalPointDef& route) {
  if (def.guess_route_from_floor) route.initial_floor = std::max(route.initial_floor, first_floor);
  if (def.guess_fallback_cap_fall > 0) route.newton_sparse.fallback_cap_fall = def.guess_fallback_cap_fall;
  if (def.guess_floor_stalls > 0) route.floor_stalls = def.guess_floor_stalls;
}

}  // namespace dc::solvers::prox
