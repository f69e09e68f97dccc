#pragma once
// The micro_step pile built at rest: the n circles of dc::stress::scaled_seed_pile(n) (r = 1,
// the same box of side 3√n m) placed as a hexagonal packing on the floor, each row offset by
// half a spacing, 0.01 m gaps and a ±0.004 m horizontal jitter (no exact symmetry), at rest.
// A few steps of settling close the gaps; from then on nearly every pair in contact carries
// load at every size, so the cost per contact row compares sizes in one regime (the falling
// pile of BM_StepOnly is mostly free rows at 10,000 bodies and more, mostly loaded at 1,000).
// Numbering: shuffled (random in space, as the generated bodies' creation order) or by the
// Morton code of the initial cell of side 2r (as `[bodies] order = "morton"`).
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world_def.hpp"
#include "world/spatial_order.hpp"

namespace dc::bench_micro {

/// scaled_seed_pile(n) with its generated bodies replaced by the packed pile, numbered in
/// Morton order (`morton`) or shuffled by a fixed seed.
inline WorldDef packed_pile(int n, bool morton) {
  WorldDef d = stress::scaled_seed_pile(n);
  d.bodies.count = 0;
  const double side = d.world.width, r = 1.0, gap = 0.01;
  const double dx = 2 * r + gap, dy = std::sqrt(3.0) * (r + gap / 2);
  std::mt19937_64 rng(20261205);
  const auto unit = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };  // U[0, 1)
  std::vector<Vec2> at;
  at.reserve(static_cast<std::size_t>(n));
  for (int row = 0; static_cast<int>(at.size()) < n; ++row) {
    const double x0 = r + gap + (row % 2 == 1 ? dx / 2 : 0.0);
    for (double x = x0; x + r + gap <= side && static_cast<int>(at.size()) < n; x += dx)
      at.push_back({x + 0.004 * (2 * unit() - 1), r + gap + row * dy});
  }
  std::vector<int> order;
  if (morton) {
    order = morton_order(at, 2 * r);
  } else {  // Fisher–Yates with the raw generator (the same on every standard library)
    order.resize(at.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
    for (std::size_t k = order.size(); k > 1; --k) std::swap(order[k - 1], order[rng() % k]);
  }
  d.body.reserve(order.size());
  for (const int k : order) {
    BodyDef b;
    b.position = at[static_cast<std::size_t>(k)];
    b.radius = r;
    d.body.push_back(b);
  }
  return d;
}

}  // namespace dc::bench_micro
