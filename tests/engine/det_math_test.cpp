// The engine's libm-free sin/cos (det_math.hpp): accuracy against long-double sinl/cosl,
// exact symmetries, agreement of det_sincos with det_sin/det_cos, and that the shape code
// (poses, regular polygons, kinematic pivots, contact gaps) uses exactly these functions.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/engine/shape.hpp"
#include "dc/engine/shape_narrow_phase.hpp"
#include "dc/engine/step_outcome.hpp"
#include "det_math.hpp"

namespace dc {
namespace {

/// |got − ref| in units of the last place of the double nearest ref (ulp of its binade).
double ulp_error(double got, long double ref) {
  const double r = static_cast<double>(ref);
  if (r == 0) return got == 0 ? 0.0 : std::numeric_limits<double>::infinity();
  int e = 0;
  std::frexp(r, &e);
  const long double ulp = std::ldexp(1.0L, e - 53);
  return static_cast<double>(std::abs(static_cast<long double>(got) - ref) / ulp);
}

/// Inputs: uniform on [−10, 10] and [−10⁶, 10⁶], the doubles next to k·π/2 (worst
/// cancellation in the reduction), tiny and subnormal values.
std::vector<double> test_inputs() {
  std::mt19937_64 g(20261202);
  std::uniform_real_distribution<double> small(-10.0, 10.0), large(-1e6, 1e6), expo(-60.0, 0.0);
  std::vector<double> x;
  for (int i = 0; i < 60000; ++i) x.push_back(small(g));
  for (int i = 0; i < 60000; ++i) x.push_back(large(g));
  for (int i = 0; i < 20000; ++i) x.push_back(std::exp2(expo(g)) * (i % 2 ? -1 : 1));
  for (int k = -20000; k <= 20000; k += 7) {
    const double m = k * (0.5 * std::numbers::pi);
    x.insert(x.end(), {m, std::nextafter(m, -1e9), std::nextafter(m, 1e9)});
  }
  x.insert(x.end(), {0.0, -0.0, 1e-300, 4.9e-324, std::numbers::pi / 4, std::numbers::pi, 1.5e6, 1.64e6});
  return x;
}

TEST(DetMath, WithinOneUlpOfLongDoubleSinAndCos) {
  // fdlibm's bound is < 1 ulp for |x| < 2²⁰·π/2; measured max ≈ 0.78 ulp (docs/reproducibility.md).
  double worst_s = 0, worst_c = 0;
  for (const double x : test_inputs()) {
    const double es = ulp_error(det_sin(x), sinl(static_cast<long double>(x)));
    const double ec = ulp_error(det_cos(x), cosl(static_cast<long double>(x)));
    ASSERT_LT(es, 1.0) << "sin " << x;
    ASSERT_LT(ec, 1.0) << "cos " << x;
    worst_s = std::max(worst_s, es);
    worst_c = std::max(worst_c, ec);
  }
  RecordProperty("max_ulp_sin", std::to_string(worst_s));
  RecordProperty("max_ulp_cos", std::to_string(worst_c));
}

TEST(DetMath, SymmetriesAndSincosAreExact) {
  for (const double x : test_inputs()) {
    const double s = det_sin(x), c = det_cos(x);
    EXPECT_EQ(det_sin(-x), -s) << x;
    EXPECT_EQ(det_cos(-x), c) << x;
    double s2 = 0, c2 = 0;
    det_sincos(x, s2, c2);
    EXPECT_EQ(s2, s) << x;
    EXPECT_EQ(c2, c) << x;
    // sin² + cos² = 1 to the rounding of two < 1 ulp values and the sum.
    EXPECT_NEAR(s * s + c * c, 1.0, 6e-16) << x;
  }
  EXPECT_TRUE(std::signbit(det_sin(-0.0)));
  EXPECT_EQ(det_cos(-0.0), 1.0);
}

TEST(DetMath, ShiftsByQuarterTurnsSwapSinAndCos) {
  // sin(x + π/2) = cos x, sin(x + π) = −sin x, cos(x + 2π) = cos x; the shifted argument is
  // rounded, so the identity holds to |x|·2⁻⁵³ plus an ulp of each side.
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  for (int i = 0; i < 20000; ++i) {
    const double x = u(g);
    const double tol = 4e-16 * (std::abs(x) + 8.0);
    EXPECT_NEAR(det_sin(x + 0.5 * std::numbers::pi), det_cos(x), tol) << x;
    EXPECT_NEAR(det_sin(x + std::numbers::pi), -det_sin(x), tol) << x;
    EXPECT_NEAR(det_cos(x + 2 * std::numbers::pi), det_cos(x), tol) << x;
  }
  // The reduction keeps the tail of π: sin(π_d) = π − π_d − O(10⁻⁴⁸) to full relative
  // precision, where π − π_d = 1.2246467991473531772e-16 rounded (fdlibm's pi_lo; long double
  // is too short to check this: its π is off by 5e-20).
  const double pi_lo = 1.2246467991473531772e-16;
  EXPECT_DOUBLE_EQ(det_sin(std::numbers::pi), pi_lo);
  EXPECT_DOUBLE_EQ(det_cos(0.5 * std::numbers::pi), 0.5 * pi_lo);
}

TEST(DetMath, HugeArgumentsReduceModuloTheDoubleTwoPi) {
  // Beyond 2²⁰·π/2 the argument is reduced exactly by fmod(x, 2π_d) (det_math.hpp).
  const double two_pi_d = 2 * std::numbers::pi;
  for (const double x : {2e6, -3.3e7, 1e12, 1e22, -1e300, std::numeric_limits<double>::max()}) {
    const double r = std::fmod(x, two_pi_d);
    EXPECT_EQ(det_sin(x), det_sin(r)) << x;
    EXPECT_EQ(det_cos(x), det_cos(r)) << x;
    // Close to the true value where q·(2π − 2π_d) is small.
    if (std::abs(x) < 1e8) {
      EXPECT_NEAR(det_sin(x), static_cast<double>(sinl(static_cast<long double>(x))), 1e-8);
    }
  }
  for (const double x : {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_TRUE(std::isnan(det_sin(x)));
    EXPECT_TRUE(std::isnan(det_cos(x)));
  }
}

/// Angles where glibc's sin/cos and det_* usually differ in the last bit somewhere.
std::vector<double> shape_angles() {
  std::mt19937_64 g(3);
  std::uniform_real_distribution<double> u(-400.0, 400.0);
  std::vector<double> a;
  for (int i = 0; i < 500; ++i) a.push_back(u(g));
  return a;
}

TEST(DetMath, ShapePosesUseDetSincos) {
  BodyState s;
  const ShapeDef box = make_box({1.0, 0.5}, "test"), ell = make_ellipse({1.0, 0.1}, "test");
  const auto angles = shape_angles();
  for (std::size_t k = 0; k < angles.size(); ++k)
    s.add_shaped(k % 2 ? box : ell, Motion::Dynamic, {3.0 * static_cast<double>(k), 5.0}, 1.0, {}, angles[k]);
  WorldDef d;
  d.world.width = d.world.height = 2000.0;
  ShapeNarrowPhase narrow;
  UniformGridBroadPhase grid;
  std::vector<Contact> contacts;
  narrow.collide(s, d, grid, contacts);
  std::vector<Vec2> wv, wn;
  for (std::size_t k = 0; k < angles.size(); ++k) {
    const int i = static_cast<int>(k);
    const ShapePose p = narrow.pose(s, i), q = make_pose(s, i, wv, wn);
    ASSERT_EQ(p.c, det_cos(angles[k])) << k;
    ASSERT_EQ(p.s, det_sin(angles[k])) << k;
    ASSERT_EQ(q.c, p.c) << k;
    ASSERT_EQ(q.s, p.s) << k;
  }
}

TEST(DetMath, RegularPolygonVerticesUseDetSincos) {
  for (int sides = 3; sides <= kMaxPolygonVertices; ++sides) {
    const double r = 0.7;
    const ShapeDef p = make_regular_polygon(sides, r, "test");
    // Vertex i at angle start + i·step (edge 0 at the bottom), then make_polygon's centroid shift.
    const double step = 2 * std::numbers::pi / sides, start = -0.5 * std::numbers::pi - 0.5 * step;
    std::vector<Vec2> v;
    for (int i = 0; i < sides; ++i) v.push_back({r * det_cos(start + i * step), r * det_sin(start + i * step)});
    const ShapeDef q = make_polygon(v, "test");
    ASSERT_EQ(p.vertices.size(), q.vertices.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      EXPECT_EQ(p.vertices[i].x, q.vertices[i].x) << sides << " " << i;
      EXPECT_EQ(p.vertices[i].y, q.vertices[i].y) << sides << " " << i;
    }
  }
}

TEST(DetMath, KinematicPivotRotationUsesDetSincos) {
  BodyState s;
  const ShapeDef box = make_box({2.8, 0.8}, "test");
  const Vec2 pivot{15.0, 15.0};
  const auto omegas = shape_angles();  // as ω Δt below: turns of up to ±400 rad per step
  for (const double w : omegas) s.add_shaped(box, Motion::Kinematic, {25.4, 15.0}, 1.0, {}, 0.0, w, true, pivot);
  const BodyState before = s;
  LcpProblem none;
  none.J.resize(0, 3 * static_cast<Eigen::Index>(s.size()));
  Eigen::VectorXd lambda(0), impulse;
  const double dt = 1.0;
  integrate_bodies(none, lambda, {0.0, -9.81}, dt, s, impulse);
  for (std::size_t k = 0; k < s.size(); ++k) {
    double sn = 0, c = 1;
    det_sincos(omegas[k] * dt, sn, c);
    const Vec2 r = before.position[k] - pivot;
    ASSERT_EQ(s.position[k].x, pivot.x + (c * r.x - sn * r.y)) << k;
    ASSERT_EQ(s.position[k].y, pivot.y + (sn * r.x + c * r.y)) << k;
  }
}

}  // namespace
}  // namespace dc
