#pragma once
// A minimal 2D vector for the engine's hot loops (plain aggregate, no aliasing surprises).
#include <cmath>

namespace dc {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;

  constexpr Vec2& operator+=(Vec2 o) { x += o.x; y += o.y; return *this; }
  constexpr Vec2& operator-=(Vec2 o) { x -= o.x; y -= o.y; return *this; }
  constexpr Vec2& operator*=(double s) { x *= s; y *= s; return *this; }
  friend constexpr Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
  friend constexpr Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
  friend constexpr Vec2 operator-(Vec2 a) { return {-a.x, -a.y}; }
  friend constexpr Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
  friend constexpr Vec2 operator*(Vec2 a, double s) { return {s * a.x, s * a.y}; }
  friend constexpr bool operator==(Vec2 a, Vec2 b) = default;
};

constexpr double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
/// 2D cross product a × b = a_x b_y − a_y b_x (the z component of the 3D cross product).
constexpr double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
/// Left perpendicular (−y, x): the contact tangent t = perp(n) of docs/design.md §2.
constexpr Vec2 perp(Vec2 a) { return {-a.y, a.x}; }
/// √(x² + y²) with IEEE sqrt (exactly rounded on every CPU), not std::hypot, whose libm
/// implementation may differ between C libraries (docs/reproducibility.md).
inline double length(Vec2 a) { return std::sqrt(a.x * a.x + a.y * a.y); }
constexpr double length_squared(Vec2 a) { return dot(a, a); }

}  // namespace dc
