#include "dc/engine/body_state.hpp"

#include <numbers>

namespace dc {

void BodyState::add(Vec2 x, double r, double rho, Vec2 v, double theta, double w) {
  const double m = rho * std::numbers::pi * r * r;  // 2D: areal density × area
  const double I = 0.5 * m * r * r;                 // solid disc about its centre
  position.push_back(x);
  angle.push_back(theta);
  velocity.push_back(v);
  omega.push_back(w);
  radius.push_back(r);
  density.push_back(rho);
  mass.push_back(m);
  inertia.push_back(I);
  // Guarded divisions: validated radius and density are > 0, but a caller building a
  // state by hand could pass 0; an infinite-mass body (inverse 0) is the safe reading.
  inv_mass.push_back(m > 0 ? 1.0 / m : 0.0);
  inv_inertia.push_back(I > 0 ? 1.0 / I : 0.0);
  if (!shapes.empty()) shapes.add(make_circle(r), Motion::Dynamic);
}

void BodyState::add_shaped(const ShapeDef& shape, Motion motion, Vec2 x, double rho, Vec2 v, double theta,
                           double w, bool has_pivot, Vec2 pivot) {
  if (shapes.empty()) shapes.add_circles(size());
  const bool dynamic = motion == Motion::Dynamic;
  const double m = dynamic ? shape.mass(rho) : 0.0;
  const double I = dynamic ? shape.inertia(rho) : 0.0;
  const bool rotates_about_pivot = motion == Motion::Kinematic && has_pivot;
  position.push_back(x);
  angle.push_back(theta);
  velocity.push_back(rotates_about_pivot ? w * perp(x - pivot) : motion == Motion::Static ? Vec2{} : v);
  omega.push_back(motion == Motion::Static ? 0.0 : w);
  radius.push_back(shape.radius);
  density.push_back(rho);
  mass.push_back(m);
  inertia.push_back(I);
  inv_mass.push_back(m > 0 ? 1.0 / m : 0.0);
  inv_inertia.push_back(I > 0 ? 1.0 / I : 0.0);
  shapes.add(shape, motion, rotates_about_pivot, pivot);
}

void BodyState::reserve(std::size_t n) {
  position.reserve(n); angle.reserve(n); velocity.reserve(n); omega.reserve(n);
  radius.reserve(n); density.reserve(n); mass.reserve(n); inertia.reserve(n);
  inv_mass.reserve(n); inv_inertia.reserve(n);
}

}  // namespace dc
