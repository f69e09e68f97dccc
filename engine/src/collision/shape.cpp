#include "dc/engine/shape.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "dc/core/error.hpp"
#include "dc/core/number_text.hpp"
#include "det_math.hpp"

namespace dc {
namespace {

[[noreturn]] void bad_shape(const std::string& where, const std::string& what) {
  throw ConfigError(where + ": " + what);
}

std::string fmt(Vec2 v) {
  std::ostringstream os;
  os << "(" << v.x << ", " << v.y << ")";
  return os.str();
}

}  // namespace

const char* shape_kind_name(ShapeKind k) {
  switch (k) {
    case ShapeKind::Circle: return "circle";
    case ShapeKind::Polygon: return "polygon";
    case ShapeKind::Ellipse: return "ellipse";
  }
  return "unknown";
}

const char* motion_name(Motion m) {
  switch (m) {
    case Motion::Dynamic: return "dynamic";
    case Motion::Static: return "static";
    case Motion::Kinematic: return "kinematic";
  }
  return "unknown";
}

Motion parse_motion(const std::string& name, const std::string& where) {
  if (name == "dynamic") return Motion::Dynamic;
  if (name == "static") return Motion::Static;
  if (name == "kinematic") return Motion::Kinematic;
  bad_shape(where, "unknown motion '" + name + "' (expected dynamic, static or kinematic)");
}

const char* to_string(BodyShape s) {
  switch (s) {
    case BodyShape::Circle: return "circle";
    case BodyShape::Box: return "box";
    case BodyShape::Polygon: return "polygon";
    case BodyShape::Ellipse: return "ellipse";
  }
  return "unknown";
}

BodyShape parse_body_shape(const std::string& name, const std::string& key) {
  for (BodyShape s : {BodyShape::Circle, BodyShape::Box, BodyShape::Polygon, BodyShape::Ellipse})
    if (name == to_string(s)) return s;
  bad_shape(key, "unknown shape '" + name + "' (expected circle, box, polygon or ellipse)");
}

double ShapeDef::area() const {
  switch (kind) {
    case ShapeKind::Circle: return std::numbers::pi * radius * radius;
    case ShapeKind::Ellipse: return std::numbers::pi * semi_axes.x * semi_axes.y;
    case ShapeKind::Polygon: {
      double a2 = 0;
      for (std::size_t i = 0; i < vertices.size(); ++i) a2 += cross(vertices[i], vertices[(i + 1) % vertices.size()]);
      return 0.5 * a2;
    }
  }
  return 0;
}

double ShapeDef::mass(double density) const {
  if (kind == ShapeKind::Circle) return density * std::numbers::pi * radius * radius;  // as BodyState::add
  return density * area();
}

double ShapeDef::inertia(double density) const {
  const double m = mass(density);
  switch (kind) {
    case ShapeKind::Circle: return 0.5 * m * radius * radius;
    case ShapeKind::Ellipse: return 0.25 * m * (semi_axes.x * semi_axes.x + semi_axes.y * semi_axes.y);
    case ShapeKind::Polygon: {
      double s = 0;
      const std::size_t n = vertices.size();
      for (std::size_t i = 0; i < n; ++i) {
        const Vec2 p = vertices[i], q = vertices[(i + 1) % n];
        s += cross(p, q) * (dot(p, p) + dot(p, q) + dot(q, q));
      }
      return density * s / 12.0;
    }
  }
  return 0;
}

ShapeDef make_circle(double r) {
  ShapeDef s;
  s.kind = ShapeKind::Circle;
  s.radius = r;
  return s;
}

ShapeDef make_polygon(const std::vector<Vec2>& v, const std::string& where) {
  const int n = static_cast<int>(v.size());
  if (n < 3 || n > kMaxPolygonVertices)
    bad_shape(where, "a polygon needs 3 to " + std::to_string(kMaxPolygonVertices) + " vertices, got " +
                         std::to_string(n));
  double scale = 0;
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i].x) || !std::isfinite(v[i].y))
      bad_shape(where, "vertex " + std::to_string(i) + " is not finite");
    scale = std::max({scale, std::abs(v[i].x), std::abs(v[i].y)});
  }
  // Area and centroid of the list as given.
  double a2 = 0;
  Vec2 c6{};
  for (int i = 0; i < n; ++i) {
    const Vec2 p = v[i], q = v[(i + 1) % n];
    const double ci = cross(p, q);
    a2 += ci;
    c6 += ci * (p + q);
  }
  if (a2 < 0) bad_shape(where, "polygon vertices are clockwise; list them counter-clockwise");
  if (!(0.5 * a2 >= 1e-10)) bad_shape(where, "polygon is degenerate (area " + g_text(0.5 * a2) + " m^2)");
  // Convexity: every turn strictly to the left (collinear or repeated vertices are degenerate).
  for (int i = 0; i < n; ++i) {
    const Vec2 p = v[(i + n - 1) % n], q = v[i], r = v[(i + 1) % n];
    const Vec2 e0 = q - p, e1 = r - q;
    const double l0 = length(e0), l1 = length(e1);
    if (!(l0 > 1e-9 * std::max(scale, 1.0)) || !(l1 > 1e-9 * std::max(scale, 1.0)))
      bad_shape(where, "polygon has a repeated vertex at " + fmt(q));
    const double turn = cross(e0, e1) / (l0 * l1);
    if (turn <= 1e-9) {
      bad_shape(where, turn < 0 ? "polygon is not convex at vertex " + std::to_string(i) + " " + fmt(q)
                                : "polygon has collinear vertices at vertex " + std::to_string(i) + " " + fmt(q));
    }
  }
  // A polygon whose turns are all left may still wind twice (a star): its edge direction then
  // turns through 4π instead of 2π. Count the full turns exactly (no atan2): each turn is
  // strictly between 0 and π, so the direction passes +x (counter-clockwise) exactly when an
  // edge with e.y < 0 is followed by one with e.y ≥ 0, once per full turn.
  int turns = 0;
  for (int i = 0; i < n; ++i) {
    const Vec2 e0 = v[i] - v[(i + n - 1) % n], e1 = v[(i + 1) % n] - v[i];
    if (e0.y < 0 && e1.y >= 0) ++turns;
  }
  if (turns > 1) bad_shape(where, "polygon winds more than once (self-intersecting)");

  ShapeDef s;
  s.kind = ShapeKind::Polygon;
  s.centroid_offset = (1.0 / (3.0 * a2)) * c6;  // Σ (p+q) c_i / (6A), A = a2/2
  s.vertices.reserve(v.size());
  s.radius = 0;
  for (const Vec2 p : v) {
    s.vertices.push_back(p - s.centroid_offset);
    s.radius = std::max(s.radius, length(s.vertices.back()));
  }
  return s;
}

ShapeDef make_box(Vec2 size, const std::string& where) {
  if (!(size.x > 0) || !(size.y > 0) || !std::isfinite(size.x) || !std::isfinite(size.y))
    bad_shape(where, "size: expected [width, height] > 0, got " + fmt(size));
  const double hx = 0.5 * size.x, hy = 0.5 * size.y;
  return make_polygon({{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}}, where);
}

ShapeDef make_regular_polygon(int sides, double r, const std::string& where) {
  if (sides < 3 || sides > kMaxPolygonVertices)
    bad_shape(where, "sides: expected 3 to " + std::to_string(kMaxPolygonVertices) + ", got " +
                         std::to_string(sides));
  if (!(r > 0) || !std::isfinite(r)) bad_shape(where, "radius: expected a circumradius > 0");
  std::vector<Vec2> v;
  const double step = 2 * std::numbers::pi / sides;
  const double start = -0.5 * std::numbers::pi - 0.5 * step;  // edge 0 at the bottom
  for (int i = 0; i < sides; ++i) {
    double c = 1, s = 0;
    det_sincos(start + i * step, s, c);  // libm-free: the same vertices on every CPU
    v.push_back({r * c, r * s});
  }
  return make_polygon(v, where);
}

ShapeDef make_ellipse(Vec2 semi_axes, const std::string& where) {
  if (!(semi_axes.x > 0) || !(semi_axes.y > 0) || !std::isfinite(semi_axes.x) || !std::isfinite(semi_axes.y))
    bad_shape(where, "semi_axes: expected [a, b] > 0, got " + fmt(semi_axes));
  ShapeDef s;
  s.kind = ShapeKind::Ellipse;
  s.semi_axes = semi_axes;
  s.radius = std::max(semi_axes.x, semi_axes.y);
  return s;
}

ShapeDef build_shape(BodyShape shape, double radius, Vec2 size, int sides, const std::vector<Vec2>& vertices,
                     Vec2 semi_axes, const std::string& where) {
  switch (shape) {
    case BodyShape::Circle:
      if (!(radius > 0) || !std::isfinite(radius)) bad_shape(where + "radius", "expected a number > 0");
      return make_circle(radius);
    case BodyShape::Box: return make_box(size, where + "shape \"box\"");
    case BodyShape::Ellipse: return make_ellipse(semi_axes, where + "shape \"ellipse\"");
    case BodyShape::Polygon:
      if (!vertices.empty() && sides != 0)
        bad_shape(where + "sides", "give either vertices or sides (a regular polygon), not both");
      if (!vertices.empty()) return make_polygon(vertices, where + "vertices");
      if (sides == 0) bad_shape(where + "shape \"polygon\"", "needs vertices = [[x, y], ...] or sides = N");
      return make_regular_polygon(sides, radius, where + "sides");
  }
  bad_shape(where + "shape", "invalid BodyShape " + std::to_string(static_cast<int>(shape)));
}

void ShapeTable::add(const ShapeDef& shape, Motion m, bool with_pivot, Vec2 p) {
  kind.push_back(shape.kind);
  motion.push_back(m);
  const std::size_t n = shape.kind == ShapeKind::Polygon ? shape.vertices.size() : 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 e = shape.vertices[(i + 1) % n] - shape.vertices[i];
    vertices.push_back(shape.vertices[i]);
    normals.push_back((1.0 / length(e)) * Vec2{e.y, -e.x});  // outward for CCW
  }
  vertex_offset.push_back(static_cast<std::int32_t>(vertices.size()));
  semi_axes.push_back(shape.kind == ShapeKind::Ellipse ? shape.semi_axes : Vec2{});
  pivot.push_back(with_pivot ? p : Vec2{});
  has_pivot.push_back(with_pivot ? 1 : 0);
}

void ShapeTable::add_circles(std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) add(make_circle(1.0), Motion::Dynamic);
}

bool ShapeTable::any_non_circle() const {
  return std::any_of(kind.begin(), kind.end(), [](ShapeKind k) { return k != ShapeKind::Circle; });
}

}  // namespace dc
