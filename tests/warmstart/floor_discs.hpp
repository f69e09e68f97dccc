#pragma once
// Test scenes of discs resting on the floor with a chosen contact history (the oracle-bound
// starters' tests: sph-residual, sph-gain, the gate, the extrapolations).
#include <initializer_list>
#include <vector>

#include <gtest/gtest.h>

#include "dc/engine/world.hpp"

namespace dc::test {

/// Discs of radius r resting exactly on the floor (gap 0) at the given x, floor only.
inline WorldDef discs_on_floor(std::initializer_list<double> xs, double r = 1.0) {
  WorldDef d;
  d.bodies.count = 0;
  d.world.walls = {false, false, true, false};
  for (const double x : xs) {
    BodyDef b;
    b.position = {x, r};
    b.radius = r;
    d.body.push_back(b);
  }
  return d;
}

/// On a collided and assembled step: stores the given λ_n (λ_t = 0) as the solved λ of each
/// disc's floor contact and puts the discs back at rest, so the next step has the same
/// contacts (same keys) with that history.
inline void integrate_and_rest(World& w, const std::vector<double>& ln) {
  ASSERT_EQ(w.contacts().size(), ln.size());
  const std::vector<Vec2> at(w.bodies().position.begin(), w.bodies().position.end());
  w.integrate(w.pack(ln, std::vector<double>(ln.size(), 0.0)));
  for (std::size_t i = 0; i < at.size(); ++i) {
    w.bodies().position[i] = at[i];
    w.bodies().velocity[i] = {0.0, 0.0};
    w.bodies().omega[i] = 0.0;
  }
}

/// One step whose solved λ_n are `ln`, then the discs back at rest (integrate_and_rest).
inline void step_with(World& w, const std::vector<double>& ln) {
  w.collide();
  w.assemble();
  integrate_and_rest(w, ln);
}

}  // namespace dc::test
