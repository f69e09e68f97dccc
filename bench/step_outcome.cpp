#include "step_outcome.hpp"

#include <cmath>

namespace dc::bench {

StepOutcome evaluate_step(const World& w, const Eigen::VectorXd& lambda, Eigen::VectorXd& impulse) {
  const LcpProblem& p = w.problem();
  const BodyState& s = w.bodies();
  const WorldDef& d = w.def();
  const double dt = d.time.dt;
  const Vec2 g = d.world.gravity;
  const int n = static_cast<int>(s.size());
  impulse = p.J.transpose() * lambda * dt;  // Δt Jᵀ λ  [N·s]

  // Same update as World::integrate, on copies of the two fields it needs.
  auto new_velocity = [&](int k) {
    const auto i = static_cast<size_t>(k);
    return s.velocity[i] + dt * g + s.inv_mass[i] * Vec2{impulse[3 * k], impulse[3 * k + 1]};
  };
  auto new_position = [&](int k) { return s.position[static_cast<size_t>(k)] + dt * new_velocity(k); };

  StepOutcome out;
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    const Vec2 v = new_velocity(k);
    const double om = s.omega[i] + s.inv_inertia[i] * impulse[3 * k + 2];
    out.energy += 0.5 * s.mass[i] * length_squared(v) + 0.5 * s.inertia[i] * om * om -
                  s.mass[i] * dot(g, s.position[i] + dt * v);
  }
  double min_gap = 0;
  for (const Contact& c : w.contacts()) {
    const auto b = static_cast<size_t>(c.body_b);
    const Vec2 xb = new_position(c.body_b);
    double gap;
    if (c.body_a >= 0) {
      gap = length(xb - new_position(c.body_a)) - s.radius[static_cast<size_t>(c.body_a)] - s.radius[b];
    } else {
      // Walls are planes: distance of the new centre along the (fixed) wall normal.
      // p = x − (r + g/2) n  ⇒  plane offset c0 = n·p − g/2.
      const double wall_coord = dot(c.point, c.normal) - 0.5 * c.gap;
      gap = dot(xb, c.normal) - wall_coord - s.radius[b];
    }
    min_gap = std::min(min_gap, gap);
  }
  out.penetration = -min_gap;
  return out;
}

}  // namespace dc::bench
