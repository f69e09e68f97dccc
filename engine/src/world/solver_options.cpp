// solver_options: a scene's [solver] section → SolverOptions (lcp_solver.hpp).
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {

SolverOptions solver_options(const SolverSection& solver) {
  SolverOptions o;
  o.max_sweeps = solver.sweeps;
  o.tolerance = solver.tolerance;
  o.omega = solver.omega;
  return o;
}

}  // namespace dc
