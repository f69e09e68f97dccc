#include "dc/engine/stress_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "dc/core/error.hpp"

namespace dc::stress {

BodyDef circle(double x, double y, double r, double rho) {
  BodyDef b;
  b.position = {x, y};
  b.radius = r;
  b.density = rho;
  return b;
}

WorldDef explicit_scene(double width, double height) {
  WorldDef d;
  d.bodies.count = 0;
  d.world.width = width;
  d.world.height = height;
  return d;
}

WorldDef pyramid_mass_ratio(double ratio, bool heavy_on_top) {
  // Box exactly 4 m wide: the bottom circles touch a wall and each other (gap 0), so the
  // walls, not friction, keep the pyramid from spreading under a heavy top.
  WorldDef d = explicit_scene(4.0, 10.0);
  const double top_rho = heavy_on_top ? ratio : 1.0, bottom_rho = heavy_on_top ? 1.0 : ratio;
  d.body.push_back(circle(1.0, 1.0, 1.0, bottom_rho));
  d.body.push_back(circle(3.0, 1.0, 1.0, bottom_rho));
  // Resting on both (centre distance 2 + 1 mm, so the explicit bodies do not overlap).
  d.body.push_back(circle(2.0, 1.0 + std::sqrt(3.0) * 1.0005, 1.0, top_rho));
  d.time.steps = 200;
  return d;
}

WorldDef stack_mass_ratio(double top_over_bottom) {
  WorldDef d = explicit_scene(10.0, 10.0);
  d.body.push_back(circle(5.0, 1.0, 1.0, 1.0));
  d.body.push_back(circle(5.0, 3.0, 1.0, top_over_bottom));
  d.time.steps = 200;
  return d;
}

WorldDef small_pile(int count, double dt, std::uint64_t seed) {
  WorldDef d;
  d.world.width = 12.0;
  d.world.height = 30.0;
  d.bodies.count = count;
  d.bodies.mean = {6.0, 12.0};
  d.bodies.sigma = 4.0;
  d.bodies.seed = seed;
  d.time.dt = dt;
  d.time.steps = static_cast<int>(std::lround(2.0 / dt));  // 2 s: fall and settle
  return d;
}

WorldDef column(int n, double mu) {
  WorldDef d = explicit_scene(10.0, 2.0 * n + 10.0);
  d.contact.friction = mu;
  for (int k = 0; k < n; ++k) d.body.push_back(circle(5.0, 1.0 + k * 2.001));
  d.time.steps = 300;
  return d;
}

WorldDef scaled_seed_pile(int count) {
  WorldDef d;
  const double side = 3.0 * std::sqrt(static_cast<double>(count));
  d.world.width = d.world.height = side;
  d.bodies.count = count;
  d.bodies.mean = {side / 2, side / 2};
  d.bodies.sigma = 0.465 * std::sqrt(static_cast<double>(count));
  return d;
}

WorldDef many_bodies(int count) {
  // Uniform areal coverage 0.25 (count·π r² = 0.25 L²) in an L × L box, so every count has the
  // same local density and the broad phase has the same work per body. The generator draws
  // Gaussian centres; with σ = 3 L the accepted ones (inside the box) are uniform to 1.5 %.
  WorldDef d;
  const double side = std::sqrt(4.0 * std::numbers::pi * count);
  d.world.width = d.world.height = side;
  d.bodies.count = count;
  d.bodies.sigma = 3.0 * side;
  d.bodies.mean = {0.5 * side, 0.5 * side};
  d.solver.sweeps = 20;
  d.time.steps = 5;
  return d;
}

WorldDef scaled_scene(double s) {
  WorldDef d = explicit_scene(10.0 * s, 10.0 * s);
  d.world.gravity = {0.0, -9.81 * s};
  d.contact.slop *= s;
  d.contact.margin *= s;
  d.contact.restitution_threshold *= s;
  // A pyramid of three resting circles, two smaller circles falling onto it off-centre.
  // (Gaps of ~1 cm: a decimal scale factor must not turn an exact touch into an overlap.)
  d.body.push_back(circle(3.0 * s, 1.0 * s, 1.0 * s));
  d.body.push_back(circle(5.01 * s, 1.0 * s, 1.0 * s));
  d.body.push_back(circle(4.005 * s, 2.75 * s, 1.0 * s));
  d.body.push_back(circle(3.3 * s, 6.0 * s, 0.5 * s));
  d.body.push_back(circle(6.5 * s, 8.0 * s, 0.7 * s));
  d.solver.sweeps = 200;
  d.solver.tolerance = 0.0;  // a tolerance in N would break the scale invariance
  d.time.steps = 150;
  return d;
}

WorldDef friction_scene(double mu, int count) {
  WorldDef d;
  d.bodies.count = count;
  d.contact.friction = mu;
  d.time.steps = 300;
  return d;
}

WorldDef exactly_touching() {
  WorldDef d = explicit_scene(30.0, 30.0);
  for (int k = 0; k < 4; ++k) d.body.push_back(circle(10.0 + 2.0 * k, 1.0));
  d.body.push_back(circle(12.0, 3.0));
  d.time.steps = 100;
  return d;
}

WorldDef corners() {
  WorldDef d = explicit_scene(30.0, 30.0);
  d.body.push_back(circle(1.0, 1.0));
  d.body.push_back(circle(29.0, 1.0));
  d.body.push_back(circle(1.0, 29.0));
  d.body.push_back(circle(29.0, 29.0));
  BodyDef thrown = circle(6.0, 6.0, 0.5);
  thrown.velocity = {-20.0, -20.0};
  d.body.push_back(thrown);
  d.time.steps = 200;
  return d;
}

WorldDef coincident_def(bool walls_and_gravity) {
  WorldDef d = explicit_scene(30.0, 30.0);
  if (!walls_and_gravity) {
    d.world.walls = {false, false, false, false};
    d.world.gravity = {0.0, 0.0};
  }
  d.time.steps = 200;
  return d;
}

BodyState coincident_state(int copies, double density_ratio) {
  BodyState s;
  for (int k = 0; k < copies; ++k) s.add({15.0, 15.0}, 1.0, k == 0 ? density_ratio : 1.0);
  return s;
}

WorldDef free_collision(int count, double ratio, double mu) {
  WorldDef d;
  d.world.walls = {false, false, false, false};
  d.world.gravity = {0.0, 0.0};
  d.contact.friction = mu;
  d.bodies.count = count;
  d.bodies.sigma = 3.0;
  BodyDef p = circle(1.0, 15.3, 1.0, ratio);
  p.velocity = {30.0, 0.0};
  p.omega = 5.0;
  d.body.push_back(p);
  d.solver.sweeps = 300;
  d.time.steps = 120;
  return d;
}

WorldDef box_stack(int n, Vec2 size) {
  WorldDef d = explicit_scene(std::max(10.0, 4 * size.x), n * size.y + 5);
  for (int k = 0; k < n; ++k) {
    BodyDef b;
    b.shape = BodyShape::Box;
    b.size = size;
    b.position = {0.5 * d.world.width, (k + 0.5) * size.y};
    d.body.push_back(b);
  }
  d.time.steps = 1000;
  return d;
}

WorldDef box_pyramid(int base) {
  WorldDef d = explicit_scene(base + 10.0, base + 5.0);
  for (int row = 0; row < base; ++row)
    for (int i = 0; i < base - row; ++i) {
      BodyDef b;
      b.shape = BodyShape::Box;
      b.position = {5.0 + 0.5 * row + i + 0.5, row + 0.5};
      d.body.push_back(b);
    }
  d.time.steps = 600;
  return d;
}

WorldDef shape_extremes(BodyShape shape, Vec2 dims, int count) {
  WorldDef d = explicit_scene(20.0, 20.0);
  d.bodies.count = count;
  d.bodies.shape = shape;
  d.bodies.size = dims;
  d.bodies.semi_axes = dims;
  d.bodies.radius = 0.5;
  d.bodies.mean = {10.0, 10.0};
  d.bodies.sigma = 3.0;
  d.time.steps = 400;
  return d;
}

}  // namespace dc::stress
