#include "dc/engine/assembly.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dc {

double friction_of(const Contact& /*contact*/, const ContactSection& section) { return section.friction; }

void assemble_lcp(const BodyState& s, const std::vector<Contact>& contacts, const WorldDef& def,
                  LcpProblem& out) {
  const int nb = static_cast<int>(s.size());
  const int nc = static_cast<int>(contacts.size());
  const double dt = def.time.dt;
  const ContactSection& cs = def.contact;

  // The constraint structure first: it says which rows each contact owns.
  ContactConstraints& con = out.constraints;
  con.clear();
  con.reserve(static_cast<size_t>(nc));
  // A static or kinematic body_a (infinite mass) owns no columns: a one-body row, like a wall.
  const bool motion_types = !s.shapes.empty();
  for (const Contact& ct : contacts)
    con.add(ct.body_a >= 0 && (!motion_types || s.shapes.is_dynamic(static_cast<size_t>(ct.body_a))) ? ct.body_a : -1,
            ct.body_b, friction_of(ct, cs), ct.key.feature);
  const int rows = con.rows();

  out.dt = dt;
  out.inv_mass.resize(3 * nb);
  for (int k = 0; k < nb; ++k) {
    out.inv_mass[3 * k] = out.inv_mass[3 * k + 1] = s.inv_mass[static_cast<size_t>(k)];
    out.inv_mass[3 * k + 2] = s.inv_inertia[static_cast<size_t>(k)];
  }

  // J: at most 6 non-zeros per row (3 per circle); walls contribute no columns.
  std::vector<Eigen::Triplet<double, int>> trip;
  trip.reserve(static_cast<size_t>(rows) * 6);
  out.b.resize(rows);
  out.lo.resize(rows);
  out.hi.resize(rows);
  out.mu.resize(rows);
  out.normal_row.assign(static_cast<size_t>(rows), -1);

  const Vec2 g = def.world.gravity;
  for (int c = 0; c < nc; ++c) {
    const Contact& ct = contacts[static_cast<size_t>(c)];
    const Vec2 n = ct.normal, t = perp(n);
    const ContactConstraint& kc = con[c];
    const int rn = kc.normal_row, rt = kc.tangent_row;
    const bool friction = kc.has_friction();
    double vn = 0, vt = 0;       // J u       (relative velocity before the step)
    double vn_f = 0, vt_f = 0;   // J Δt M⁻¹ F_ext  (gravity only: Δt·g on linear dofs)
    auto add_body = [&](int body, double sign) {
      const auto k = static_cast<size_t>(body);
      const Vec2 r = ct.point - s.position[k];
      const double rn_x = cross(r, n), rt_x = cross(r, t);
      trip.emplace_back(rn, 3 * body, sign * n.x);
      trip.emplace_back(rn, 3 * body + 1, sign * n.y);
      trip.emplace_back(rn, 3 * body + 2, sign * rn_x);
      vn += sign * (dot(n, s.velocity[k]) + rn_x * s.omega[k]);
      vn_f += sign * dt * dot(n, g);
      if (friction) {
        trip.emplace_back(rt, 3 * body, sign * t.x);
        trip.emplace_back(rt, 3 * body + 1, sign * t.y);
        trip.emplace_back(rt, 3 * body + 2, sign * rt_x);
        vt += sign * (dot(t, s.velocity[k]) + rt_x * s.omega[k]);
        vt_f += sign * dt * dot(t, g);
      }
    };
    if (kc.body_a >= 0) {
      add_body(ct.body_a, -1.0);
    } else if (ct.body_a >= 0) {
      // Static / kinematic body_a: no columns, no gravity; its velocity at the point enters b
      // as a moving boundary's (relative velocity J u with the boundary's u).
      const auto k = static_cast<size_t>(ct.body_a);
      const Vec2 r = ct.point - s.position[k];
      vn -= dot(n, s.velocity[k]) + cross(r, n) * s.omega[k];
      vt -= dot(t, s.velocity[k]) + cross(r, t) * s.omega[k];
    }
    add_body(ct.body_b, +1.0);

    // b of the normal row: relative velocity + gravity + stabilisation + restitution.
    double bn = vn + vn_f;
    if (ct.gap > 0) {
      bn += ct.gap / dt;  // speculative: may close at most the open gap this step
    } else {
      bn += cs.baumgarte * std::min(0.0, ct.gap + cs.slop) / dt;
    }
    // Restitution (restitution.hpp): aim at −e·v_a, v_a the stored approach velocity.
    if (cs.restitution > 0 && ct.restitution_due && ct.approach_velocity < -cs.restitution_threshold)
      bn = std::min(bn, vn + vn_f + cs.restitution * ct.approach_velocity);
    out.b[rn] = bn;
    out.lo[rn] = 0.0;
    out.hi[rn] = std::numeric_limits<double>::infinity();
    out.mu[rn] = 0.0;
    if (friction) {
      out.b[rt] = vt + vt_f;
      out.lo[rt] = -std::numeric_limits<double>::infinity();  // effective bounds: ±μ λ_n
      out.hi[rt] = std::numeric_limits<double>::infinity();
      out.mu[rt] = kc.mu;
      out.normal_row[static_cast<size_t>(rt)] = rn;
    }
  }
  out.J.resize(rows, 3 * nb);
  out.J.setFromTriplets(trip.begin(), trip.end());
  out.J.makeCompressed();
  // A = J M⁻¹ Jᵀ Δt is formed on demand only (LcpProblem::ensure_assembled_matrix).
  out.A = SparseRowMatrix();
}

}  // namespace dc
