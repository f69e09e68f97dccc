#include "world/restitution.hpp"

namespace dc {

double relative_normal_velocity(const BodyState& s, const Contact& c) {
  // Same expression as a normal row of J times u (assembly.cpp): Σ ± (n·v + (r × n) ω).
  auto body_velocity = [&](int body) {
    const auto k = static_cast<size_t>(body);
    return dot(c.normal, s.velocity[k]) + cross(c.point - s.position[k], c.normal) * s.omega[k];
  };
  double vn = body_velocity(c.body_b);
  if (c.body_a >= 0) vn -= body_velocity(c.body_a);
  return vn;
}

void track_approach_velocities(const BodyState& s, std::span<const Contact> previous,
                               std::span<Contact> current) {
  const std::vector<int> match = match_contacts_by_key(previous, current);
  for (std::size_t c = 0; c < current.size(); ++c) {
    Contact& ct = current[c];
    const Contact* p = match[c] >= 0 ? &previous[static_cast<size_t>(match[c])] : nullptr;
    if (p == nullptr || !(p->lambda_n > 0)) {
      ct.approach_velocity = relative_normal_velocity(s, ct);
      ct.restitution_due = ct.gap <= 0;
    } else if (!p->restitution_due && p->approach_velocity != 0) {
      ct.approach_velocity = p->approach_velocity;
      ct.restitution_due = true;
    } else {
      ct.approach_velocity = 0;
      ct.restitution_due = false;
    }
  }
}

}  // namespace dc
