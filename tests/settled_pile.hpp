#pragma once
// Test helper shared by the suites (engine and up): advance a world a number of steps with PGS
// at a fixed sweep budget — a pile forms or settles — then collide and assemble the next step.
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"

namespace dc::test {

/// w.step(pgs, max_sweeps = sweeps) `steps` times, then w.collide() and w.assemble(): returns
/// the next step's LCP (w.problem()).
inline const LcpProblem& step_then_assemble(World& w, int steps, int sweeps) {
  const auto pgs = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = sweeps;
  for (int s = 0; s < steps; ++s) w.step(*pgs, o);
  w.collide();
  return w.assemble();
}

}  // namespace dc::test
