#include "dc/engine/world_def.hpp"

#include <cmath>
#include <sstream>

#include "dc/core/error.hpp"
#include "dc/engine/shape.hpp"
#include "world_def_limits.hpp"

namespace dc {
namespace {

[[noreturn]] void bad(const std::string& key, const std::string& expected, double got) {
  std::ostringstream os;
  os << key << ": expected " << expected << ", got " << got;
  throw ConfigError(os.str());
}
void finite(const std::string& key, double v) {
  if (!std::isfinite(v)) bad(key, "a finite number", v);
}
void positive(const std::string& key, double v) {
  finite(key, v);
  if (!(v > 0)) bad(key, "a number > 0", v);
}
void non_negative(const std::string& key, double v) {
  finite(key, v);
  if (!(v >= 0)) bad(key, "a number >= 0", v);
}

/// A region [x0, y0, x1, y1]: finite; all zero (unset) or x1 > x0 and y1 > y0.
void region(const std::string& key, const std::array<double, 4>& r, bool required) {
  for (std::size_t i = 0; i < 4; ++i) finite(key + "[" + std::to_string(i) + "]", r[i]);
  const bool unset = r[0] == 0 && r[1] == 0 && r[2] == 0 && r[3] == 0;
  if (unset && !required) return;
  if (!(r[2] > r[0]) || !(r[3] > r[1])) {
    std::ostringstream os;
    os << key << ": expected [x0, y0, x1, y1] with x1 > x0 and y1 > y0, got [" << r[0] << ", " << r[1] << ", "
       << r[2] << ", " << r[3] << "]";
    throw ConfigError(os.str());
  }
}
void radius_max(const std::string& key, double v, double radius) {
  non_negative(key, v);
  if (v != 0 && !(v >= radius)) bad(key, "0 or a number >= radius (" + std::to_string(radius) + ")", v);
}

/// The shape keys a shape may not use (a circle's size) must still be finite numbers.
void finite_shape_values(const std::string& key, Vec2 size, Vec2 semi_axes, const std::vector<Vec2>& vertices) {
  finite(key + "size[0]", size.x);
  finite(key + "size[1]", size.y);
  finite(key + "semi_axes[0]", semi_axes.x);
  finite(key + "semi_axes[1]", semi_axes.y);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    finite(key + "vertices[" + std::to_string(i) + "][0]", vertices[i].x);
    finite(key + "vertices[" + std::to_string(i) + "][1]", vertices[i].y);
  }
}

}  // namespace

const char* to_string(BodyOrder o) { return o == BodyOrder::Morton ? "morton" : "creation"; }
const char* to_string(InternalOrder o) {
  switch (o) {
    case InternalOrder::Morton: return "morton";
    case InternalOrder::Auto: return "auto";
    case InternalOrder::None: break;
  }
  return "none";
}

BodyOrder parse_body_order(const std::string& name, const std::string& key) {
  if (name == "creation") return BodyOrder::Creation;
  if (name == "morton") return BodyOrder::Morton;
  throw ConfigError(key + ": expected \"creation\" or \"morton\", got \"" + name + "\"");
}

InternalOrder parse_internal_order(const std::string& name, const std::string& key) {
  if (name == "none") return InternalOrder::None;
  if (name == "morton") return InternalOrder::Morton;
  if (name == "auto") return InternalOrder::Auto;
  throw ConfigError(key + ": expected \"none\", \"morton\" or \"auto\", got \"" + name + "\"");
}

void WorldDef::validate() const {
  positive("[world] width", world.width);
  positive("[world] height", world.height);
  finite("[world] gravity[0]", world.gravity.x);
  finite("[world] gravity[1]", world.gravity.y);
  positive("[time] dt", time.dt);
  if (time.steps < 0) bad("[time] steps", "an integer >= 0", time.steps);
  non_negative("[contact] friction", contact.friction);
  non_negative("[contact] restitution", contact.restitution);
  if (contact.restitution > 1) bad("[contact] restitution", "a number in [0, 1]", contact.restitution);
  non_negative("[contact] baumgarte", contact.baumgarte);
  if (contact.baumgarte > 1) bad("[contact] baumgarte", "a number in [0, 1]", contact.baumgarte);
  non_negative("[contact] slop", contact.slop);
  non_negative("[contact] margin", contact.margin);
  non_negative("[contact] restitution_threshold", contact.restitution_threshold);
  if (solver.sweeps < 1) bad("[solver] sweeps", "an integer >= 1", solver.sweeps);
  non_negative("[solver] tolerance", solver.tolerance);
  if (solver.relax_sweeps < 0) bad("[solver] relax_sweeps", "an integer >= 0", solver.relax_sweeps);
  positive("[solver] omega", solver.omega);
  if (solver.omega >= 2) bad("[solver] omega", "a number in (0, 2)", solver.omega);
  if (bodies.count < 0) bad("[bodies] count", "an integer >= 0", bodies.count);
  positive("[bodies] radius", bodies.radius);
  positive("[bodies] density", bodies.density);
  finite("[bodies] mean[0]", bodies.mean.x);
  finite("[bodies] mean[1]", bodies.mean.y);
  non_negative("[bodies] sigma", bodies.sigma);
  if (bodies.max_attempts < 1) bad("[bodies] max_attempts", "an integer >= 1", bodies.max_attempts);
  finite_shape_values("[bodies] ", bodies.size, bodies.semi_axes, bodies.vertices);
  (void)build_shape(bodies.shape, bodies.radius, bodies.size, bodies.sides, bodies.vertices, bodies.semi_axes,
                    "[bodies] ");
  radius_max("[bodies] radius_max", bodies.radius_max, bodies.radius);
  region("[bodies] region", bodies.region, false);
  if (bodies.resort_every < 1)
    throw ConfigError("[bodies] resort_every: expected an integer >= 1, got " + std::to_string(bodies.resort_every));
  if (!(bodies.resort_decay > 1) || !std::isfinite(bodies.resort_decay))
    throw ConfigError("[bodies] resort_decay: expected a finite number > 1, got " + std::to_string(bodies.resort_decay));
  non_negative("[inflow] rate", inflow.rate);
  // Every value is finite even where it is unused (an inactive inflow, a circle's size): a NaN
  // in a scene is a mistake wherever it stands.
  for (std::size_t i = 0; i < 4; ++i) finite("[inflow] region[" + std::to_string(i) + "]", inflow.region[i]);
  finite("[inflow] start", inflow.start);
  finite("[inflow] stop", inflow.stop);
  finite("[inflow] velocity[0]", inflow.velocity.x);
  finite("[inflow] velocity[1]", inflow.velocity.y);
  finite("[inflow] radius", inflow.radius);
  finite("[inflow] radius_max", inflow.radius_max);
  finite("[inflow] density", inflow.density);
  if (inflow.active()) {
    region("[inflow] region", inflow.region, true);
    non_negative("[inflow] start", inflow.start);
    if (!(inflow.stop > inflow.start)) bad("[inflow] stop", "a time > [inflow] start", inflow.stop);
    positive("[inflow] radius", inflow.radius);
    radius_max("[inflow] radius_max", inflow.radius_max, inflow.radius);
    positive("[inflow] density", inflow.density);
    if (inflow.max_attempts < 1) bad("[inflow] max_attempts", "an integer >= 1", inflow.max_attempts);
  }
  for (std::size_t i = 0; i < body.size(); ++i) {
    const std::string k = "[[body]] #" + std::to_string(i + 1) + " ";
    const BodyDef& b = body[i];
    finite(k + "position[0]", b.position.x);
    finite(k + "position[1]", b.position.y);
    finite(k + "velocity[0]", b.velocity.x);
    finite(k + "velocity[1]", b.velocity.y);
    finite(k + "angle", b.angle);
    finite(k + "omega", b.omega);
    positive(k + "radius", b.radius);
    positive(k + "density", b.density);
    finite_shape_values(k, b.size, b.semi_axes, b.vertices);
    (void)build_shape(b.shape, b.radius, b.size, b.sides, b.vertices, b.semi_axes, k);
    const Motion m = b.motion;
    if (b.pivot) {
      finite(k + "pivot[0]", b.pivot->x);
      finite(k + "pivot[1]", b.pivot->y);
      if (m != Motion::Kinematic) throw ConfigError(k + "pivot: only a kinematic body has a pivot");
    }
    non_negative(k + "spawn", b.spawn);
    if (b.spawn > 0 && (b.shape != BodyShape::Circle || m != Motion::Dynamic))
      throw ConfigError(k + "spawn: only a dynamic circle can enter later (spawn > 0)");
  }
  validate_derived_quantities(*this);  // masses, energies and counts the values imply
}

}  // namespace dc
