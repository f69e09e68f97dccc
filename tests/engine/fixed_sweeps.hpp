#pragma once
// Solver options for exactly k sweeps (no tolerance stop): the engine tests that compare
// iterates or states bit for bit after a fixed amount of work.
#include "dc/lcp/lcp_solver.hpp"

namespace dc::test {

inline SolverOptions fixed_sweeps(int k) {
  SolverOptions o;
  o.max_sweeps = k;
  o.tolerance = 0.0;
  return o;
}

}  // namespace dc::test
