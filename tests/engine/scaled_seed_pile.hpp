#pragma once
// The seed scene scaled to n circles at the seed's density — box side 3√n m, the Gaussian's mean at
// the centre, σ = 0.465√n m (30 m and 4.65 m for the seed's 100) —, the family of micro_step and
// benchmarks/scripts/step-scaling.sh, for the tests of body orders.
#include <cmath>

#include "dc/engine/world_def.hpp"

namespace dc::test {

inline WorldDef scaled_seed_pile(int n) {
  WorldDef d;
  const double side = 3.0 * std::sqrt(static_cast<double>(n));
  d.world.width = d.world.height = side;
  d.bodies.count = n;
  d.bodies.mean = {side / 2, side / 2};
  d.bodies.sigma = 0.465 * std::sqrt(static_cast<double>(n));
  return d;
}

}  // namespace dc::test
