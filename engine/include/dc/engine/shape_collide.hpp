#pragma once
// Narrow phase for non-circle shapes (docs/design.md §8.1, docs/engine.md "Shapes"); circle–
// circle and circle–wall are in narrow_phase.hpp. Polygon–wall, ellipse–wall (deepest vertices /
// support point), circle–polygon (Voronoi regions) and polygon–polygon (separating axes, Box2D's
// b2FindMaxSeparation) are analytic and exact. Pairs with an ellipse go to libccd (GJK+EPA by
// default, or MPR) with each shape inflated by its speculative reach δ, so gap = δ_a + δ_b −
// depth, then the normal is polished by maximising n·(s_b(−n) − s_a(n)) over its angle.
// Polygon–polygon gives up to two points: reference face (largest separation, or the one most
// aligned with libccd's normal on request), incident face clipped against its side planes
// (Sutherland–Hodgman), points below reference face + threshold; feature ids from the (edge,
// vertex) indices. libccd is 3D: a 2D shape is a prism of half-height H > any in-plane depth,
// so the minimum-penetration direction is always in the plane.
#include <cstdint>

#include "dc/core/vec2.hpp"
#include "dc/engine/shape.hpp"

namespace dc {

/// One body's shape in the world frame for one step.
struct ShapePose {
  ShapeKind kind = ShapeKind::Circle;
  Vec2 x;                     ///< centre of mass (world) [m]
  double c = 1.0, s = 0.0;    ///< cos θ, sin θ
  double radius = 0.0;        ///< circle radius, or bounding radius
  const Vec2* vertices = nullptr;  ///< polygon: world-frame vertices (CCW)
  const Vec2* normals = nullptr;   ///< polygon: world-frame outward edge normals
  int count = 0;              ///< polygon: vertex count
  Vec2 semi;                  ///< ellipse: (a, b)

  [[nodiscard]] Vec2 rotate(Vec2 v) const { return {c * v.x - s * v.y, s * v.x + c * v.y}; }
  [[nodiscard]] Vec2 unrotate(Vec2 v) const { return {c * v.x + s * v.y, -s * v.x + c * v.y}; }
  /// Support point s(d) = argmax_{p ∈ shape} d·p (world frame; d need not be unit).
  [[nodiscard]] Vec2 support(Vec2 d) const;
};

/// One contact point of a pair, normal from a to b.
struct ContactPoint {
  Vec2 point;       ///< midway between the surfaces [m]
  Vec2 normal;      ///< unit, from a to b (from the wall into the body)
  double gap = 0;   ///< signed distance [m]
  Vec2 on_a, on_b;  ///< witness points on each surface (world) [m]
  int feature = 0;  ///< ContactKey::feature
};

enum class CcdMethod : std::uint8_t { GjkEpa = 0, Mpr = 1 };

/// Fills the world-frame vertices and normals of a polygon body (`local`, `local_normals`:
/// body frame) for angle θ given as (c, s).
void transform_polygon(const Vec2* local, const Vec2* local_normals, int count, double c, double s, Vec2 x,
                       Vec2* world, Vec2* world_normals);

/// Up to two contact points of shapes a and b with gap < threshold. `inflate_a`, `inflate_b`
/// (their speculative reaches, summing to threshold) inflate the shapes for libccd. Returns
/// the number of points written to out[0..1]. Either shape may be a circle (a circle pair
/// belongs to circle_circle, but works here too, through libccd).
/// Polygon pairs use the separating-axis test for the reference face (exact, and robust where
/// libccd's normal is not: at touching, GJK and MPR return an arbitrary direction) unless
/// `polygon_sat` is false (then libccd's normal picks it; for the benchmark and the tests).
int collide_shapes(const ShapePose& a, const ShapePose& b, double inflate_a, double inflate_b, ContactPoint out[2],
                   CcdMethod method = CcdMethod::GjkEpa, bool polygon_sat = true);

/// Contact points of shape k against the plane through `origin` with unit normal `n` (a wall;
/// n points into the box) with gap < threshold; out[i].on_a lies on the plane.
int collide_shape_plane(const ShapePose& k, Vec2 n, double offset, double threshold, ContactPoint out[2]);

/// The libccd part alone (for the micro-benchmark and tests): normal (a → b) and gap of the
/// inflated pair, or false when the inflated shapes do not overlap.
bool ccd_normal_gap(const ShapePose& a, const ShapePose& b, double inflate_a, double inflate_b, CcdMethod method,
                    Vec2& normal, double& gap);

/// Analytic circle (a) – polygon (b) test, exact; exposed for the micro-benchmark.
int collide_circle_polygon(const ShapePose& circle, const ShapePose& polygon, double threshold, bool circle_is_a,
                           ContactPoint out[1]);

}  // namespace dc
