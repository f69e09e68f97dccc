// Shapes (docs/design.md §8.1): mass properties, validation, scene keys, and the narrow phase
// (analytic vs libccd, two-point manifolds, speculative distances, feature ids).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/shape.hpp"
#include "dc/engine/shape_collide.hpp"
#include "dc/engine/shape_narrow_phase.hpp"
#include "dc/engine/world.hpp"

namespace dc {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Shape, BoxMassAndInertiaAreTheRectangleFormulas) {
  const ShapeDef b = make_box({2.0, 0.5}, "t");
  const double rho = 3.0, m = rho * 2.0 * 0.5;
  EXPECT_NEAR(b.area(), 1.0, 1e-14);
  EXPECT_NEAR(b.mass(rho), m, 1e-14);
  EXPECT_NEAR(b.inertia(rho), m * (4.0 + 0.25) / 12.0, 1e-13);
  EXPECT_NEAR(b.radius, std::sqrt(1.0 + 0.0625), 1e-14);
}

TEST(Shape, PolygonIsShiftedToItsCentroidAndInertiaIsAboutIt) {
  // A right triangle with legs 3 (x) and 6 (y): centroid (1, 2), I_c = m (a² + b²)/18.
  const ShapeDef t = make_polygon({{0, 0}, {3, 0}, {0, 6}}, "t");
  EXPECT_NEAR(t.centroid_offset.x, 1.0, 1e-14);
  EXPECT_NEAR(t.centroid_offset.y, 2.0, 1e-14);
  const double m = t.mass(1.0);
  EXPECT_NEAR(m, 9.0, 1e-13);
  EXPECT_NEAR(t.inertia(1.0), m * (9.0 + 36.0) / 18.0, 1e-12);
  // Shifting a box off the origin changes nothing about its inertia about the centroid.
  const ShapeDef far = make_polygon({{10, 10}, {12, 10}, {12, 11}, {10, 11}}, "t");
  EXPECT_NEAR(far.inertia(1.0), make_box({2, 1}, "t").inertia(1.0), 1e-11);
}

TEST(Shape, EllipseAndRegularPolygonMassProperties) {
  const ShapeDef e = make_ellipse({1.5, 0.5}, "t");
  const double m = 2.0 * std::numbers::pi * 1.5 * 0.5;
  EXPECT_NEAR(e.mass(2.0), m, 1e-13);
  EXPECT_NEAR(e.inertia(2.0), m * (2.25 + 0.25) / 4.0, 1e-13);
  // A 16-gon of circumradius 1 is nearly a disc: area n/2 sin(2π/n), inertia → ½ m r² from below.
  const ShapeDef p = make_regular_polygon(16, 1.0, "t");
  EXPECT_NEAR(p.area(), 8.0 * std::sin(2 * std::numbers::pi / 16), 1e-12);
  EXPECT_LT(p.inertia(1.0), 0.5 * p.mass(1.0));
  EXPECT_GT(p.inertia(1.0), 0.45 * p.mass(1.0));
  // Edge 0 is at the bottom (horizontal), so a regular polygon rests flat.
  EXPECT_NEAR(p.vertices[0].y, p.vertices[1].y, 1e-14);
  EXPECT_LT(p.vertices[0].y, 0.0);
}

TEST(Shape, InvalidPolygonsAreOneLineErrorsNamingTheBody) {
  auto scene = [](const std::string& body) {
    return [body] { parse_scene("[bodies]\ncount = 0\n[[body]]\nposition = [5.0, 5.0]\n" + body, "s.toml"); };
  };
  const std::string cw = error_of(scene("shape = \"polygon\"\nvertices = [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]]\n"));
  EXPECT_NE(cw.find("[[body]] #1"), std::string::npos) << cw;
  EXPECT_NE(cw.find("clockwise"), std::string::npos) << cw;
  const std::string concave = error_of(
      scene("shape = \"polygon\"\nvertices = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.3], [2.0, 2.0], [0.0, 2.0]]\n"));
  EXPECT_NE(concave.find("not convex"), std::string::npos) << concave;
  const std::string two = error_of(scene("shape = \"polygon\"\nvertices = [[0.0, 0.0], [2.0, 0.0]]\n"));
  EXPECT_NE(two.find("3 to 16"), std::string::npos) << two;
  const std::string line =
      error_of(scene("shape = \"polygon\"\nvertices = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]]\n"));
  EXPECT_NE(line.find("collinear"), std::string::npos) << line;
  const std::string tiny =
      error_of(scene("shape = \"polygon\"\nvertices = [[0.0, 0.0], [1e-6, 0.0], [0.0, 1e-6]]\n"));
  EXPECT_NE(tiny.find("degenerate"), std::string::npos) << tiny;
  EXPECT_NE(error_of(scene("shape = \"hexagon\"\n")).find("unknown shape"), std::string::npos);
  EXPECT_NE(error_of(scene("motion = \"moving\"\n")).find("unknown motion"), std::string::npos);
  EXPECT_NE(error_of(scene("pivot = [1.0, 1.0]\n")).find("only a kinematic body"), std::string::npos);
  EXPECT_NE(error_of(scene("shape = \"box\"\nsize = [0.0, 1.0]\n")).find("size"), std::string::npos);
  for (const std::string& e : {cw, concave, two, line, tiny}) EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(Shape, SceneKeysRoundTripThroughToml) {
  const WorldDef d = parse_scene(R"(
[bodies]
count = 3
shape = "ellipse"
semi_axes = [0.8, 0.3]
[[body]]
position = [10.0, 3.0]
shape = "box"
size = [4.0, 0.5]
motion = "static"
angle = 0.2
[[body]]
position = [10.0, 20.0]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [0.0, 1.0]]
motion = "kinematic"
omega = 0.5
pivot = [15.0, 15.0]
[[body]]
position = [20.0, 20.0]
shape = "polygon"
sides = 6
radius = 0.7
)",
                                 "s.toml");
  ASSERT_EQ(d.body.size(), 3u);
  EXPECT_EQ(d.body[1].pivot, (Vec2{15.0, 15.0}));
  EXPECT_FALSE(d.body[0].pivot.has_value());
  EXPECT_EQ(parse_scene(scene_to_toml(d), "round-trip"), d);
  World w(d);
  const BodyState& s = w.bodies();
  ASSERT_EQ(s.shapes.size(), 6u);
  EXPECT_EQ(s.shapes.kind[0], ShapeKind::Ellipse);
  EXPECT_EQ(s.shapes.motion[3], Motion::Static);
  EXPECT_EQ(s.inv_mass[3], 0.0);
  EXPECT_EQ(s.shapes.vertex_count(4), 3);
  EXPECT_EQ(s.shapes.vertex_count(5), 6);
  // The kinematic body rotating about its pivot moves with v = ω × (x − p).
  EXPECT_NEAR(s.velocity[4].x, -0.5 * (20.0 - 15.0), 1e-12);
  EXPECT_NEAR(s.velocity[4].y, 0.5 * (10.0 - 15.0), 1e-12);
}

TEST(Shape, CircleOnlyScenesHaveNoShapeTable) {
  World w(default_world_def());
  EXPECT_TRUE(w.bodies().shapes.empty());
}

ShapePose box_pose(Vec2 x, double theta, std::vector<Vec2>& wv, std::vector<Vec2>& wn, Vec2 size = {1, 1}) {
  BodyState s;
  s.add_shaped(make_box(size, "t"), Motion::Dynamic, x, 1.0, {}, theta);
  return make_pose(s, 0, wv, wn);
}

ShapePose circle_pose(Vec2 x, double r) {
  ShapePose p;
  p.kind = ShapeKind::Circle;
  p.x = x;
  p.radius = r;
  return p;
}

TEST(ShapeCollide, FaceOnFaceGivesTwoPointsWithTheSpeculativeDistance) {
  std::vector<Vec2> va, na, vb, nb;
  const ShapePose a = box_pose({0, 0}, 0.0, va, na, {2, 1});
  const ShapePose b = box_pose({0.3, 1.01}, 0.0, vb, nb);  // 0.01 above, shifted right
  // The SAT path (the engine's) and the libccd-normal path (GJK+EPA, MPR) give the same points.
  for (const int path : {0, 1, 2}) {
    const CcdMethod m = path == 2 ? CcdMethod::Mpr : CcdMethod::GjkEpa;
    const bool sat = path == 0;
    ContactPoint pts[2];
    ASSERT_EQ(collide_shapes(a, b, 0.05, 0.05, pts, m, sat), 2);
    for (const ContactPoint& p : pts) {
      EXPECT_NEAR(p.gap, 0.01, 1e-9);
      EXPECT_NEAR(p.normal.y, 1.0, 1e-9);
      EXPECT_NEAR(p.point.y, 0.505, 1e-9);
    }
    EXPECT_NEAR(std::min(pts[0].point.x, pts[1].point.x), -0.2, 1e-9);
    EXPECT_NEAR(std::max(pts[0].point.x, pts[1].point.x), 0.8, 1e-9);
    EXPECT_NE(pts[0].feature, pts[1].feature);
    // Beyond the inflated reach: no contact.
    EXPECT_EQ(collide_shapes(a, b, 0.004, 0.004, pts, m, sat), 0);
  }
}

TEST(ShapeCollide, FeatureIdsStayWhenTheBoxMovesSlightly) {
  std::vector<Vec2> va, na, vb, nb;
  const ShapePose a = box_pose({0, 0}, 0.0, va, na, {4, 1});
  ContactPoint p0[2], p1[2];
  ASSERT_EQ(collide_shapes(a, box_pose({0.0, 0.99}, 0.01, vb, nb), 0.02, 0.02, p0), 2);
  ASSERT_EQ(collide_shapes(a, box_pose({0.05, 0.995}, -0.01, vb, nb), 0.02, 0.02, p1), 2);
  const auto sorted = [](ContactPoint* p) { return std::minmax(p[0].feature, p[1].feature); };
  EXPECT_EQ(sorted(p0), sorted(p1));
}

TEST(ShapeCollide, CirclePolygonAnalyticAgreesWithLibccd) {
  std::vector<Vec2> vb, nb;
  const ShapePose box = box_pose({0, 0}, 0.3, vb, nb, {2, 1});
  // Around the box: face regions, vertex regions, slight overlaps and speculative gaps.
  for (int k = 0; k < 24; ++k) {
    const double phi = 2 * std::numbers::pi * k / 24;
    const ShapePose c = circle_pose({1.55 * std::cos(phi), 1.2 * std::sin(phi)}, 0.5);
    ContactPoint analytic[1];
    const int na_ = collide_circle_polygon(c, box, 0.4, true, analytic);
    Vec2 n;
    double gap = 0;
    const bool hit = ccd_normal_gap(c, box, 0.2, 0.2, CcdMethod::GjkEpa, n, gap);
    ASSERT_EQ(na_ == 1, hit) << "phi " << phi;
    if (!hit) continue;
    // libccd alone stops at its tolerance (EPA on the inflated, rounded box: ~1e-5 m).
    EXPECT_NEAR(analytic[0].gap, gap, 1e-4) << "phi " << phi;
    EXPECT_NEAR(dot(analytic[0].normal, n), 1.0, 1e-4) << "phi " << phi;
  }
}

TEST(ShapeCollide, EllipseWallIsTheSupportPoint) {
  ShapePose e;
  e.kind = ShapeKind::Ellipse;
  e.x = {0, 2};
  e.semi = {2, 1};
  e.radius = 2;
  const double th = 0.4;
  e.c = std::cos(th);
  e.s = std::sin(th);
  ContactPoint pts[2];
  ASSERT_EQ(collide_shape_plane(e, {0, 1}, 0.0, 10.0, pts), 1);
  // Lowest point of a rotated ellipse: y_c − √(a² sin²θ + b² cos²θ).
  EXPECT_NEAR(pts[0].gap, 2.0 - std::sqrt(4 * e.s * e.s + e.c * e.c), 1e-12);
}

TEST(ShapeCollide, EllipsePairGapMatchesLibccdMethods) {
  ShapePose a, b;
  a.kind = b.kind = ShapeKind::Ellipse;
  a.semi = b.semi = {1.0, 0.4};
  a.radius = b.radius = 1.0;
  a.x = {0, 0};
  b.x = {0, 0.81};  // axis-aligned, stacked: gap 0.01
  for (const CcdMethod m : {CcdMethod::GjkEpa, CcdMethod::Mpr}) {
    ContactPoint pts[2];
    ASSERT_EQ(collide_shapes(a, b, 0.05, 0.05, pts, m), 1);
    EXPECT_NEAR(pts[0].gap, 0.01, 1e-6);
    EXPECT_NEAR(pts[0].normal.y, 1.0, 1e-6);
  }
}

}  // namespace
}  // namespace dc
