#include "world_def_limits.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "dc/core/error.hpp"
#include "dc/engine/shape.hpp"

namespace dc {
namespace {

[[noreturn]] void refuse(const std::string& key, const std::string& what, double value, const std::string& why) {
  std::ostringstream os;
  os << key << ": " << what << " = " << value << " " << why;
  throw ConfigError(os.str());
}

/// One body's mass properties and energy scale within [1/kMaxMagnitude, kMaxMagnitude].
void check_body(const std::string& key, const ShapeDef& shape, double density, Vec2 position, Vec2 velocity,
                double omega, const WorldDef& def) {
  const double m = shape.mass(density), inertia = shape.inertia(density);
  const auto within = [&](const char* what, double v) {
    if (!std::isfinite(v) || v > kMaxMagnitude)
      refuse(key, what, v, "overflows: scene values must keep it <= 1e100 (docs/robustness.md)");
    if (v < 1.0 / kMaxMagnitude)
      refuse(key, what, v, "is too small: its inverse would overflow (must be >= 1e-100, docs/robustness.md)");
  };
  within("mass [kg]", m);
  within("rotational inertia [kg m^2]", inertia);
  // Energy scale: potential energy against either wall at the body's farthest position,
  // plus the kinetic energy.
  const double reach = std::abs(position.x) + std::abs(position.y);
  const double energy = m * (length(def.world.gravity) * reach + 0.5 * dot(velocity, velocity)) +
                        0.5 * inertia * omega * omega;
  if (!std::isfinite(energy) || energy > kMaxMagnitude)
    refuse(key, "energy scale m (|g| (|x| + |y|) + v^2/2) + I w^2/2 [J]", energy,
           "overflows: scene values must keep it <= 1e100 (docs/robustness.md)");
}

/// The farthest corner (x, y ≥ 0) a generated body can start at: the region's, or the
/// Gaussian's mean + 6σ, within the box.
Vec2 farthest_start(const WorldDef& def) {
  const auto& R = def.bodies.region;
  const bool region = !(R[0] == 0 && R[1] == 0 && R[2] == 0 && R[3] == 0);
  const double x = region ? R[2] : def.bodies.mean.x + 6 * def.bodies.sigma;
  const double y = region ? R[3] : def.bodies.mean.y + 6 * def.bodies.sigma;
  return {std::min(std::abs(x), def.world.width), std::min(std::abs(y), def.world.height)};
}

/// Area [m²] the generated bodies' centres can use: the region (or the Gaussian's 6σ disk)
/// clipped to the box, widened by one radius on each side.
double placement_area(const WorldDef& def, double r) {
  const auto& R = def.bodies.region;
  const double W = def.world.width, H = def.world.height;
  if (!(R[0] == 0 && R[1] == 0 && R[2] == 0 && R[3] == 0)) {
    const double w = std::min(R[2] + r, W) - std::max(R[0] - r, 0.0);
    const double h = std::min(R[3] + r, H) - std::max(R[1] - r, 0.0);
    return std::max(w, 0.0) * std::max(h, 0.0);
  }
  const double reach = 6 * def.bodies.sigma + r;
  return std::min(W * H, std::numbers::pi * reach * reach);
}

}  // namespace

void validate_generated_count(const WorldDef& def) {
  const BodiesSection& b = def.bodies;
  if (b.count > kMaxGeneratedBodies) {
    throw ConfigError("[bodies] count: " + std::to_string(b.count) + " bodies is more than the limit of " +
                      std::to_string(kMaxGeneratedBodies) + " (docs/robustness.md)");
  }
  if (b.count == 0) return;
  const ShapeDef shape = build_shape(b.shape, b.radius, b.size, b.sides, b.vertices, b.semi_axes, "[bodies] ");
  // The smallest body of a radius spread is radius itself: the least area they can cover.
  const double covered = static_cast<double>(b.count) * shape.area();
  const double densest = std::numbers::pi / std::sqrt(12.0);  // hexagonal packing of circles
  const double room = placement_area(def, shape.radius);
  if (covered > densest * room) {
    std::ostringstream os;
    os << "[bodies] count: " << b.count << " bodies cover " << covered << " m^2, more than the densest packing ("
       << 100 * densest << " %) of the " << room << " m^2 where they are placed; lower count or size, or enlarge "
       << "the box, region or sigma";
    throw ConfigError(os.str());
  }
}

void validate_derived_quantities(const WorldDef& def) {
  const BodiesSection& b = def.bodies;
  if (b.count > 0) {
    const ShapeDef shape = build_shape(b.shape, b.radius, b.size, b.sides, b.vertices, b.semi_axes, "[bodies] ");
    const Vec2 far = farthest_start(def);
    check_body("[bodies]", shape, b.density, far, {}, 0.0, def);
    if (b.radius_max > b.radius)
      check_body("[bodies] (radius_max)", make_circle(b.radius_max), b.density, far, {}, 0.0, def);
  }
  for (std::size_t i = 0; i < def.body.size(); ++i) {
    const BodyDef& d = def.body[i];
    const std::string key = "[[body]] #" + std::to_string(i + 1);
    const ShapeDef shape = build_shape(d.shape, d.radius, d.size, d.sides, d.vertices, d.semi_axes, key + " ");
    check_body(key, shape, d.density, d.position, d.velocity, d.omega, def);
  }
  if (def.inflow.active()) {
    const InflowSection& in = def.inflow;
    const Vec2 far{std::abs(in.region[2]), std::abs(in.region[3])};
    check_body("[inflow]", make_circle(std::max(in.radius, in.radius_max)), in.density, far, in.velocity, 0.0, def);
    check_body("[inflow]", make_circle(in.radius), in.density, far, in.velocity, 0.0, def);
  }
}

}  // namespace dc
