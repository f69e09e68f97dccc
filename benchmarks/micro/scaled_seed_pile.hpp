#pragma once
// micro_step's pile: the seed scene scaled to n circles at the seed's density (box side 3√n m,
// the Gaussian's mean at the centre, σ = 0.465√n m), and the options of a fixed-sweep solve.
// Shared by the benchmarks that time whole steps of it (micro_step, step_threads).
#include <cmath>

#include "dc/engine/world_def.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace dc::bench_micro {

inline WorldDef scaled_seed_pile(int n) {
  WorldDef def = default_world_def();
  const double side = 3.0 * std::sqrt(static_cast<double>(n));
  def.world.width = def.world.height = side;
  def.bodies.count = n;
  def.bodies.mean = {side / 2, side / 2};
  def.bodies.sigma = 0.465 * std::sqrt(static_cast<double>(n));
  return def;
}

/// Exactly `sweeps` sweeps (no tolerance stop, no θ record).
inline SolverOptions fixed_sweeps(int sweeps) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = 0.0;
  o.record_theta = false;
  return o;
}

}  // namespace dc::bench_micro
