#pragma once
// The box-pile scene of scenes/box_pile.toml with a given seed, stepped `steps` times with
// pgs-colored (at most 1000 sweeps to a loose 1e-2 tolerance, builtin warm start): the
// degenerate piles the prox-newton lead tests solve at steps 250 and on.
#include <cstdint>
#include <string>

#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace dc::test {

/// The scene's definition with `seed` (the caller reads its gravity).
inline WorldDef box_pile_def(int seed) {
  WorldDef def = load_scene(std::string(DC_SOURCE_DIR) + "/scenes/box_pile.toml");
  def.bodies.seed = static_cast<std::uint64_t>(seed);
  return def;
}

/// Steps `w` `steps` times with pgs-colored, loosely solved.
inline void settle_box_pile(World& w, int steps) {
  const auto warm = make_solver("pgs-colored");
  SolverOptions wo;
  wo.max_sweeps = 1000;
  wo.tolerance = 1e-2;
  wo.record_theta = false;
  for (int k = 0; k < steps; ++k) w.step(*warm, wo, World::WarmStart::PreviousLambda);
}

}  // namespace dc::test
