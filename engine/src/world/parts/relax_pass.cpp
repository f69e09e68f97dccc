// The bias-free relax pass of a step (relax_pass.hpp).
#include "world/parts/relax_pass.hpp"

#include <algorithm>

#include "world/parts/impulse_parts.hpp"

namespace dc {

void remove_position_bias(std::span<const Contact> contacts, const ContactConstraints& cons, const ContactSection& cs,
                          double dt, Eigen::Ref<Eigen::VectorXd> b) {
  const int nc = cons.size();
  for (int c = 0; c < nc; ++c) {
    const Contact& ct = contacts[static_cast<size_t>(c)];
    if (ct.gap > 0) continue;  // speculative rows keep g/Δt: the pair may close at most its gap
    if (cs.restitution > 0 && ct.restitution_due && ct.approach_velocity < -cs.restitution_threshold) continue;
    b[cons[c].normal_row] -= cs.baumgarte * std::min(0.0, ct.gap + cs.slop) / dt;
  }
}

void shift_positions(const LcpProblem& p, const Eigen::VectorXd& lambda_b, const Eigen::Ref<const Eigen::VectorXd>& lambda_r, double dt,
                     BodyState& s, Eigen::VectorXd& dl, Eigen::VectorXd& impulse) {
  if (p.rows() == 0) return;
  dl = lambda_b - lambda_r;
  auto update = [&](int c0, int c1) {  // bodies [c0 / 3, c1 / 3), their impulse final
    for (int k = c0 / 3; k < c1 / 3; ++k) {
      const auto i = static_cast<size_t>(k);
      s.position[i] += dt * (s.inv_mass[i] * Vec2{impulse[3 * k], impulse[3 * k + 1]});
      s.angle[i] += dt * (s.inv_inertia[i] * impulse[3 * k + 2]);
    }
  };
  contact_impulse(p.J, dl, dt, impulse, update);
}

}  // namespace dc
