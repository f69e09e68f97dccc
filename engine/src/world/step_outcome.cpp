#include "dc/engine/step_outcome.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "collision/narrow_phase.hpp"
#include "dc/core/error.hpp"
#include "det_math.hpp"
#include "world/parts/impulse_parts.hpp"
#include "world/parts/integrate_keeping.hpp"

namespace dc {
namespace {

/// integrate_bodies for a scene with a shape table: dynamic bodies as in the circle loop;
/// static bodies stay; kinematic bodies move with their prescribed v, ω, or rotate about their
/// pivot p: x ← p + R(ω Δt)(x − p), v = ω × (x − p).
void integrate_with_motion(const Eigen::VectorXd& impulse, Vec2 g, double dt, BodyState& s) {
  const int n = static_cast<int>(s.size());
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    switch (s.shapes.motion[i]) {
      case Motion::Dynamic:
        s.velocity[i] += dt * g + s.inv_mass[i] * Vec2{impulse[3 * k], impulse[3 * k + 1]};
        s.omega[i] += s.inv_inertia[i] * impulse[3 * k + 2];
        s.position[i] += dt * s.velocity[i];
        s.angle[i] += dt * s.omega[i];
        break;
      case Motion::Static: break;
      case Motion::Kinematic:
        if (s.shapes.has_pivot[i]) {
          const Vec2 p = s.shapes.pivot[i], r = s.position[i] - p;
          double c = 1, sn = 0;
          det_sincos(s.omega[i] * dt, sn, c);  // libm-free: the pivot rotation is bit-equal on every CPU
          s.position[i] = p + Vec2{c * r.x - sn * r.y, sn * r.x + c * r.y};
          s.velocity[i] = s.omega[i] * perp(s.position[i] - p);
        } else {
          s.position[i] += dt * s.velocity[i];
        }
        s.angle[i] += dt * s.omega[i];
        break;
    }
  }
}

}  // namespace

namespace {

/// integrate_bodies' size checks: λ has a value per row and J 3 columns per body.
void check_sizes(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, int n) {
  if (lambda.size() != p.rows())
    throw InvalidArgument("integrate_bodies: lambda has " + std::to_string(lambda.size()) +
                          " entries, the problem has " + std::to_string(p.rows()) + " rows");
  if (p.rows() > 0 && p.J.cols() != 3 * n)
    throw InvalidArgument("integrate_bodies: J has " + std::to_string(p.J.cols()) + " columns for " +
                          std::to_string(n) + " bodies");
}

/// Δt · Jᵀ λ into `impulse` after the size checks (integrate_bodies' contact impulse), then
/// done(c0, c1) on ranges of whole bodies' columns as they become final (contact_impulse).
void checked_contact_impulse(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, double dt, int n,
                             Eigen::VectorXd& impulse, ColumnsDone done, int threads = 1) {
  check_sizes(p, lambda, n);
  // Contact impulse per dof: Δt · Jᵀ λ  [N·s]
  if (p.rows() > 0) {
    contact_impulse(p.J, lambda, dt, impulse, done, threads);
  } else {
    impulse = Eigen::VectorXd::Zero(3 * n);
    done(0, 3 * n);
  }
}

}  // namespace

void integrate_bodies_keeping(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Vec2 g, double dt, BodyState& s,
                              Eigen::VectorXd& impulse, std::vector<Vec2>& x0, std::vector<Vec2>& v0,
                              std::vector<double>& w0, int threads) {
  if (!s.shapes.empty()) {
    x0 = s.position;
    v0 = s.velocity;
    w0 = s.omega;
    integrate_bodies(p, lambda, g, dt, s, impulse);
    return;
  }
  const int n = static_cast<int>(s.size());
  check_sizes(p, lambda, n);
  x0.swap(s.position);
  v0.swap(s.velocity);
  w0.swap(s.omega);
  s.position.resize(x0.size());
  s.velocity.resize(v0.size());
  s.omega.resize(w0.size());
  // integrate_bodies' updates with the old values read from the swapped arrays (a += b is a + b),
  // body by body as the impulse's columns become final (on the thread that made them final).
  auto update = [&](int c0, int c1) {
    for (int k = c0 / 3; k < c1 / 3; ++k) {
      const auto i = static_cast<size_t>(k);
      s.velocity[i] = v0[i] + (dt * g + s.inv_mass[i] * Vec2{impulse[3 * k], impulse[3 * k + 1]});
      s.omega[i] = w0[i] + s.inv_inertia[i] * impulse[3 * k + 2];
      s.position[i] = x0[i] + dt * s.velocity[i];
      s.angle[i] += dt * s.omega[i];
    }
  };
  checked_contact_impulse(p, lambda, dt, n, impulse, update, threads);
}

void integrate_bodies(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Vec2 g, double dt, BodyState& s,
                      Eigen::VectorXd& impulse) {
  integrate_bodies_on(p, lambda, g, dt, s, impulse, 1);
}

void integrate_bodies_on(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, Vec2 g, double dt, BodyState& s,
                         Eigen::VectorXd& impulse, int threads) {
  const int n = static_cast<int>(s.size());
  if (!s.shapes.empty()) {
    auto none = [](int, int) {};
    checked_contact_impulse(p, lambda, dt, n, impulse, none);
    integrate_with_motion(impulse, g, dt, s);
    return;
  }
  auto update = [&](int c0, int c1) {  // bodies [c0 / 3, c1 / 3), their impulse final
    for (int k = c0 / 3; k < c1 / 3; ++k) {
      const auto i = static_cast<size_t>(k);
      s.velocity[i] += dt * g + s.inv_mass[i] * Vec2{impulse[3 * k], impulse[3 * k + 1]};
      s.omega[i] += s.inv_inertia[i] * impulse[3 * k + 2];
      s.position[i] += dt * s.velocity[i];
      s.angle[i] += dt * s.omega[i];
    }
  };
  checked_contact_impulse(p, lambda, dt, n, impulse, update, threads);
}

double kinetic_energy(const BodyState& s) {
  double e = 0;
  for (std::size_t k = 0; k < s.size(); ++k)
    e += 0.5 * s.mass[k] * length_squared(s.velocity[k]) + 0.5 * s.inertia[k] * s.omega[k] * s.omega[k];
  return e;
}

double potential_energy(const BodyState& s, Vec2 g) {
  double e = 0;
  for (std::size_t k = 0; k < s.size(); ++k) e -= s.mass[k] * dot(g, s.position[k]);
  return e;
}

double StepOutcome::max_penetration() const {
  double min_gap = 0;
  for (const double g : gap) min_gap = std::min(min_gap, g);
  return -min_gap;
}

void predict_step(const BodyState& bodies, std::span<const Contact> contacts, const LcpProblem& problem,
                  const WorldDef& def, const Eigen::VectorXd& lambda, StepOutcome& out) {
  out.bodies = bodies;
  integrate_bodies(problem, lambda, def.world.gravity, def.time.dt, out.bodies, out.impulse);
  out.kinetic_energy = kinetic_energy(out.bodies);
  out.potential_energy = potential_energy(out.bodies, def.world.gravity);
  out.gap.resize(contacts.size());
  for (std::size_t c = 0; c < contacts.size(); ++c)
    out.gap[c] = contact_gap(out.bodies, contacts[c], def.world.width, def.world.height);
}

}  // namespace dc
