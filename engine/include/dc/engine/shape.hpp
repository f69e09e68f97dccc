#pragma once
// Body shapes and motion types (docs/design.md §8.1–8.2, docs/engine.md "Shapes"). A body is a
// circle (radius r), a convex polygon (3..16 counter-clockwise body-frame vertices, centroid at
// the origin; make_box, make_regular_polygon) or an ellipse (semi-axes a, b along body x, y).
// Mass from the areal density ρ:
//   polygon, c_i = v_i × v_{i+1}:  A = ½ Σ c_i,  centroid = Σ (v_i + v_{i+1}) c_i / (6A),
//     I = ρ/12 Σ c_i (v_i·v_i + v_i·v_{i+1} + v_{i+1}·v_{i+1})  (about the centroid)
//   ellipse:  m = ρ π a b,  I = m (a² + b²)/4
// A body's position is its centre of mass, so an off-centre vertex list is shifted
// (ShapeDef::centroid_offset says by how much). Static and kinematic bodies have infinite mass
// (inverse mass and inertia 0), contacts with dynamic bodies only and no columns in J; a
// kinematic body moves with its prescribed velocities, optionally about a world pivot (drums):
// x ← p + R(ω Δt)(x − p), v = ω × (x − p).
#include <cstdint>
#include <string>
#include <vector>

#include "dc/core/vec2.hpp"

namespace dc {

enum class ShapeKind : std::uint8_t { Circle = 0, Polygon = 1, Ellipse = 2 };
enum class Motion : std::uint8_t { Dynamic = 0, Static = 1, Kinematic = 2 };

/// The shape a scene asks for (`shape` of [bodies] and [[body]], BodyDef, BodiesSection): a
/// box is built as a ShapeKind::Polygon (make_box), so it has no ShapeKind of its own.
enum class BodyShape : std::uint8_t { Circle, Box, Polygon, Ellipse };

/// "circle" / "polygon" / "ellipse"; "dynamic" / "static" / "kinematic".
const char* shape_kind_name(ShapeKind k);
const char* motion_name(Motion m);
/// Parses a motion name; throws ConfigError "<where>: unknown motion '<name>' ..." otherwise.
Motion parse_motion(const std::string& name, const std::string& where);
/// "circle" / "box" / "polygon" / "ellipse" (the scene files' spelling).
const char* to_string(BodyShape s);
/// Parses a shape name; throws ConfigError "<key>: unknown shape '<name>' (expected circle,
/// box, polygon or ellipse)" otherwise (key = "[bodies] shape", "[[body]] #3 shape", …).
BodyShape parse_body_shape(const std::string& name, const std::string& key);

/// Polygons: at most this many vertices (and at least 3).
inline constexpr int kMaxPolygonVertices = 16;

/// One body's shape, built and validated: what the engine stores per body.
struct ShapeDef {
  ShapeKind kind = ShapeKind::Circle;
  double radius = 1.0;          ///< circle radius; for other shapes the bounding radius max |v| [m]
  std::vector<Vec2> vertices;   ///< polygon: CCW, body frame, centroid at the origin [m]
  Vec2 semi_axes;               ///< ellipse: (a, b) [m]; (0, 0) otherwise
  Vec2 centroid_offset;         ///< polygon: centroid of the vertices as given (subtracted) [m]

  /// Area [m²].
  [[nodiscard]] double area() const;
  /// Mass [kg] and rotational inertia about the centroid [kg·m²] for density ρ.
  [[nodiscard]] double mass(double density) const;
  [[nodiscard]] double inertia(double density) const;
};

/// A circle of radius r.
ShapeDef make_circle(double r);
/// A convex polygon from CCW vertices; shifts them so the centroid is the origin. Throws
/// ConfigError "<where>: ..." (one line) for fewer than 3 or more than 16 vertices, a
/// non-finite vertex, clockwise order, a non-convex or degenerate (collinear, repeated)
/// vertex list, or an area below 1e-10 m².
ShapeDef make_polygon(const std::vector<Vec2>& vertices, const std::string& where);
/// A w × h rectangle centred on the origin (w, h > 0, else ConfigError).
ShapeDef make_box(Vec2 size, const std::string& where);
/// A regular polygon with `sides` (3..16) vertices on a circle of radius r, one edge at the
/// bottom (parallel to the body's x axis) so it rests flat.
ShapeDef make_regular_polygon(int sides, double r, const std::string& where);
/// An ellipse with semi-axes a, b > 0.
ShapeDef make_ellipse(Vec2 semi_axes, const std::string& where);

/// The shape a scene's keys describe (docs/scenes.md): shape = Circle (radius), Box (size),
/// Polygon (vertices, or sides + radius for a regular one) or Ellipse (semi_axes). Throws
/// ConfigError "<where> <key>: ..." for conflicting keys (both vertices and sides) or an
/// invalid shape.
ShapeDef build_shape(BodyShape shape, double radius, Vec2 size, int sides,
                     const std::vector<Vec2>& vertices, Vec2 semi_axes, const std::string& where);

/// The shape of every body, as flat parallel arrays (the layout of the trajectory file's
/// shape table). Empty when every body is a dynamic circle: then the engine runs its circle
/// path unchanged (bit-identical to the circle-only engine).
struct ShapeTable {
  std::vector<ShapeKind> kind;            ///< per body
  std::vector<Motion> motion;             ///< per body
  std::vector<std::int32_t> vertex_offset{0};  ///< per body + 1: body k's vertices are [off[k], off[k+1])
  std::vector<Vec2> vertices;             ///< body-frame polygon vertices, concatenated
  std::vector<Vec2> normals;              ///< outward unit edge normals (edge i: v_i → v_{i+1})
  std::vector<Vec2> semi_axes;            ///< per body: ellipse (a, b), else (0, 0)
  std::vector<Vec2> pivot;                ///< per body: kinematic rotation centre (world) [m]
  std::vector<std::uint8_t> has_pivot;    ///< per body: 1 when pivot applies

  [[nodiscard]] bool empty() const { return kind.empty(); }
  [[nodiscard]] std::size_t size() const { return kind.size(); }
  /// Appends one body. `pivot` is used only when has_pivot.
  void add(const ShapeDef& shape, Motion motion, bool has_pivot = false, Vec2 pivot = {});
  /// Appends n dynamic circles (back-fills the bodies added before the first shape).
  void add_circles(std::size_t n);
  [[nodiscard]] int vertex_count(std::size_t k) const { return vertex_offset[k + 1] - vertex_offset[k]; }
  [[nodiscard]] bool is_dynamic(std::size_t k) const { return motion[k] == Motion::Dynamic; }
  /// True when some body is not a circle (the narrow phase needs shape dispatch).
  [[nodiscard]] bool any_non_circle() const;

  friend bool operator==(const ShapeTable&, const ShapeTable&) = default;
};

}  // namespace dc
