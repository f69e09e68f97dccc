#pragma once
// Three discs (two on the floor, one in the air) under a sideways pull, for the warm-starter
// tests: builtin's key matching, copy and the registry.
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"

namespace dc::test {

inline SolverOptions tight() {
  SolverOptions o;
  o.max_sweeps = 5000;
  o.tolerance = 1e-12;
  return o;
}

/// Discs of radii 1, 1.5, 1.2: discs 0 and 1 rest on the floor, disc 2 floats far above it.
inline World three_discs() {
  WorldDef d;
  d.bodies.count = 0;
  d.world.width = d.world.height = 100.0;
  d.world.walls = {false, false, true, false};
  d.world.gravity = {0.5, -9.81};  // a sideways pull: non-zero friction forces
  const double radii[3] = {1.0, 1.5, 1.2};
  const double x[3] = {10.0, 20.0, 30.0}, y[3] = {1.0, 1.5, 60.0};
  for (int k = 0; k < 3; ++k) {
    BodyDef b;
    b.position = {x[k], y[k]};
    b.radius = radii[k];
    d.body.push_back(b);
  }
  return World(d);
}

/// three_discs() after one tight step, collided and assembled again: the next step's problem.
inline World three_discs_next_step() {
  World w = three_discs();
  w.step(*make_solver("pgs"), tight());
  w.collide();
  w.assemble();
  return w;
}

}  // namespace dc::test
