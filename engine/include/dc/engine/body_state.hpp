#pragma once
// The state of all circles, stored as parallel arrays (structure of arrays) because the
// solver and the grid transfer stream over one field at a time.
#include <cstddef>
#include <vector>

#include "dc/core/vec2.hpp"
#include "dc/engine/shape.hpp"

namespace dc {

struct BodyState {
  // Kinematic state (SI units).
  std::vector<Vec2> position;    ///< centre x_k [m]
  std::vector<double> angle;     ///< orientation θ_k [rad]
  std::vector<Vec2> velocity;    ///< linear velocity v_k [m/s]
  std::vector<double> omega;     ///< angular velocity ω_k [rad/s]
  // Constant properties.
  std::vector<double> radius;    ///< r_k [m]
  std::vector<double> density;   ///< ρ_k [kg/m²] (areal density, 2D)
  std::vector<double> mass;      ///< m_k = ρ π r² [kg]
  std::vector<double> inertia;   ///< I_k = ½ m r² [kg·m²]
  std::vector<double> inv_mass;  ///< 1/m_k [1/kg]
  std::vector<double> inv_inertia;  ///< 1/I_k [1/(kg·m²)]
  /// Shapes and motion types (shape.hpp). Empty while every body is a dynamic circle (the
  /// seed's case: the engine then runs its circle-only path); filled for all bodies as soon
  /// as one body is added with add_shaped(). radius is then the bounding radius.
  ShapeTable shapes;

  [[nodiscard]] std::size_t size() const { return position.size(); }

  /// Appends one circle; computes mass and inertia from radius and density.
  void add(Vec2 x, double r, double rho, Vec2 v = {}, double theta = 0.0, double w = 0.0);
  /// Appends a body of any shape and motion. Static and kinematic bodies get mass, inertia
  /// and their inverses 0 (infinite mass: no columns in J, no energy); dynamic ones get them
  /// from the shape and density. A kinematic body keeps `v` and `w` as its prescribed motion
  /// (with a pivot: rotation about it at ω; v is then set from ω × (x − pivot)).
  void add_shaped(const ShapeDef& shape, Motion motion, Vec2 x, double rho, Vec2 v = {}, double theta = 0.0,
                  double w = 0.0, bool has_pivot = false, Vec2 pivot = {});
  /// True when body k obeys the LCP (always, for a scene without a shape table).
  [[nodiscard]] bool is_dynamic(std::size_t k) const { return shapes.empty() || shapes.is_dynamic(k); }
  void reserve(std::size_t n);
};

}  // namespace dc
