#pragma once
// Small single-disc worlds for the analytic physics tests (bounce, incline, side wall): one
// disc of radius 1 and density 1 (m = π, I = ½ m r² = π/2) in a wide box, stepped by a PGS
// solve tight enough that the LCP's conditions hold to ~1e-12.
#include <numbers>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"

namespace dc::test {

inline constexpr double kDiscMass = std::numbers::pi;           // ρ π r², ρ = 1, r = 1
inline constexpr double kDiscInertia = 0.5 * std::numbers::pi;  // ½ m r² (not read from the engine)

/// One disc (r = 1, ρ = 1) at `x` with velocity `v`; only the walls flagged exist
/// (left, right, bottom, top); a 200 × 200 box so that absent walls are far away.
inline WorldDef one_disc(Vec2 x, Vec2 v, Vec2 gravity, double mu, std::array<bool, 4> walls) {
  WorldDef d;
  d.bodies.count = 0;
  d.world.width = d.world.height = 200.0;
  d.world.gravity = gravity;
  d.world.walls = walls;
  d.contact.friction = mu;
  BodyDef b;
  b.position = x;
  b.velocity = v;
  d.body.push_back(b);
  return d;
}

/// The explicit bodies of `d` as a BodyState, without World(def)'s inside-the-box and
/// overlap checks (for starting configurations that penetrate a wall).
inline World world_unchecked(const WorldDef& d) {
  BodyState s;
  for (const BodyDef& b : d.body) s.add(b.position, b.radius, b.density, b.velocity, b.angle, b.omega);
  return World(d, s);
}

inline SolverOptions tight_options() {
  SolverOptions o;
  o.max_sweeps = 5000;
  o.tolerance = 1e-13;
  return o;
}

}  // namespace dc::test
