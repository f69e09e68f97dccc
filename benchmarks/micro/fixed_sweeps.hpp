#pragma once
// The options of a fixed-sweep solve, shared by the benchmarks that time whole steps of
// dc::stress::scaled_seed_pile (micro_step, step_threads).
#include "dc/lcp/lcp_solver.hpp"

namespace dc::bench_micro {

/// Exactly `sweeps` sweeps (no tolerance stop, no θ record).
inline SolverOptions fixed_sweeps(int sweeps) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = 0.0;
  o.record_theta = false;
  return o;
}

}  // namespace dc::bench_micro
