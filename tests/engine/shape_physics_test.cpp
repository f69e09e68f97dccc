// Classic rigid-body tests of shapes and static/kinematic bodies (docs/design.md §8): a box at rest,
// a box on a static ramp (sticks / slides), a disc rolling down a static ramp, a tall box
// tipping past its balance angle, a 20-box stack, an ellipse on its flat side and on its tip,
// a kinematic drum turning a pile.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "physics_fixtures.hpp"

namespace dc {
namespace {

using test::tight_options;
constexpr double kG = 9.81;
constexpr double kPi = std::numbers::pi;

WorldDef empty_world(double mu, std::array<bool, 4> walls = {false, false, true, false}) {
  WorldDef d;
  d.bodies.count = 0;
  d.world.width = d.world.height = 100.0;
  d.world.walls = walls;
  d.contact.friction = mu;
  return d;
}

BodyDef box(Vec2 x, Vec2 size, double angle = 0.0, Motion motion = Motion::Dynamic) {
  BodyDef b;
  b.shape = BodyShape::Box;
  b.position = x;
  b.size = size;
  b.angle = angle;
  b.motion = motion;
  return b;
}

/// λ⁰ = the previous step's λ of the contact with the same key (the builtin warm start).
World::InitialGuess warm_start() {
  return [](const World& w) {
    const auto match = match_contacts_by_key(w.previous_contacts(), w.contacts());
    std::vector<double> ln(w.contacts().size(), 0.0), lt(w.contacts().size(), 0.0);
    for (std::size_t c = 0; c < match.size(); ++c)
      if (match[c] >= 0) {
        ln[c] = w.previous_contacts()[static_cast<size_t>(match[c])].lambda_n;
        lt[c] = w.previous_contacts()[static_cast<size_t>(match[c])].lambda_t;
      }
    return w.pack(ln, lt);
  };
}

TEST(ShapePhysics, BoxAtRestCarriesItsWeightOnTwoEqualPoints) {
  WorldDef d = empty_world(0.5);
  d.body.push_back(box({50, 0.25}, {2.0, 0.5}));
  World w(d);
  const auto pgs = make_solver("pgs");
  for (int s = 0; s < 50; ++s) w.step(*pgs, tight_options());
  const double m = 2.0 * 0.5;
  ASSERT_EQ(w.contacts().size(), 2u);
  const double l0 = w.contacts()[0].lambda_n, l1 = w.contacts()[1].lambda_n;
  EXPECT_NEAR(l0 + l1, m * kG, 1e-6 * m * kG);
  EXPECT_NEAR(l0, l1, 1e-6 * m * kG);
  EXPECT_NEAR(w.bodies().position[0].y, 0.25, 0.01);
  EXPECT_NEAR(w.bodies().angle[0], 0.0, 1e-9);
}

TEST(ShapePhysics, OffCentreLoadSplitsByTheLever) {
  // A plank (12 × 0.5, m = 6) on two static discs 10 m apart, its centre 4 m from the left
  // one: the supports carry m g · 6/10 and m g · 4/10 (one point each, circle–polygon).
  WorldDef d = empty_world(0.5, {false, false, false, false});
  for (const double x : {20.0, 30.0}) {
    BodyDef c;
    c.position = {x, 10};
    c.radius = 0.5;
    c.motion = Motion::Static;
    d.body.push_back(c);
  }
  d.body.push_back(box({24, 10.75}, {12, 0.5}));
  World w(d);
  const auto pgs = make_solver("pgs");
  for (int s = 0; s < 30; ++s) w.step(*pgs, tight_options());
  ASSERT_EQ(w.contacts().size(), 2u);
  double left = 0, right = 0;
  for (const Contact& c : w.contacts()) (c.point.x < 25 ? left : right) += c.lambda_n;
  const double mg = 6.0 * kG;
  EXPECT_NEAR(left, 0.6 * mg, 1e-3 * mg);
  EXPECT_NEAR(right, 0.4 * mg, 1e-3 * mg);
}

/// A static ramp of angle θ (a long thin box) and a dynamic body resting on it, `along` metres
/// up the slope from the ramp's centre. Returns the world; the body is index 1.
WorldDef ramp(double theta, double mu, const BodyDef& body_on_top, double half_height) {
  WorldDef d = empty_world(mu, {false, false, false, false});
  const Vec2 c{50, 50}, n{-std::sin(theta), std::cos(theta)};
  d.body.push_back(box(c, {60, 1}, theta, Motion::Static));
  BodyDef b = body_on_top;
  b.position = c + (0.5 + half_height) * n;
  b.angle = theta;
  d.body.push_back(b);
  return d;
}

double along_slope(const World& w, double theta) {
  return dot(w.bodies().position[1] - Vec2{50, 50}, {std::cos(theta), std::sin(theta)});
}
double speed_along_slope(const World& w, double theta) {
  return dot(w.bodies().velocity[1], {std::cos(theta), std::sin(theta)});
}

TEST(ShapePhysics, BoxOnStaticRampSticksBelowTheFrictionAngle) {
  const double mu = 0.5, theta = 20 * kPi / 180;  // tan θ = 0.36 < μ
  World w(ramp(theta, mu, box({}, {2.0, 0.5}), 0.25));
  const auto pgs = make_solver("pgs");
  for (int s = 0; s < 100; ++s) w.step(*pgs, tight_options());
  EXPECT_NEAR(along_slope(w, theta), 0.0, 1e-3);
  EXPECT_NEAR(speed_along_slope(w, theta), 0.0, 1e-6);
}

TEST(ShapePhysics, BoxOnStaticRampSlidesWithGSinMinusMuGCos) {
  const double mu = 0.3, theta = 30 * kPi / 180;  // tan θ = 0.58 > μ
  World w(ramp(theta, mu, box({}, {2.0, 0.5}), 0.25));
  const auto pgs = make_solver("pgs");
  const int steps = 100;
  for (int s = 0; s < steps; ++s) w.step(*pgs, tight_options());
  const double t = steps * w.def().time.dt;
  const double a_exact = -kG * (std::sin(theta) - mu * std::cos(theta));  // downhill = −along
  EXPECT_NEAR(speed_along_slope(w, theta) / t, a_exact, 0.02 * std::abs(a_exact));
  EXPECT_NEAR(w.bodies().angle[1], theta, 1e-3);  // slides flat, does not tip
}

TEST(ShapePhysics, DiscRollsDownStaticRampWithTwoThirdsGSinTheta) {
  const double theta = 20 * kPi / 180;
  BodyDef disc;
  disc.radius = 1.0;
  World w(ramp(theta, 0.5, disc, 1.0));
  const auto pgs = make_solver("pgs");
  const int steps = 100;
  for (int s = 0; s < steps; ++s) w.step(*pgs, tight_options());
  const double t = steps * w.def().time.dt;
  const double a_exact = -2.0 / 3.0 * kG * std::sin(theta);
  EXPECT_NEAR(speed_along_slope(w, theta) / t, a_exact, 0.02 * std::abs(a_exact));
  // Rolling without slip: v = −ω r along the slope.
  EXPECT_NEAR(speed_along_slope(w, theta), -w.bodies().omega[1] * 1.0, 0.02 * std::abs(w.bodies().omega[1]));
}

/// A 1 × 3 box standing on its bottom-left corner, tilted by φ (CCW).
World tilted_tall_box(double phi) {
  WorldDef d = empty_world(0.8);
  const double w = 1.0, h = 3.0;
  d.body.push_back(box({50, 0.5 * w * std::sin(phi) + 0.5 * h * std::cos(phi)}, {w, h}, phi));
  return World(d);
}

TEST(ShapePhysics, TallBoxTipsPastItsBalanceAngleAndNotBefore) {
  const double balance = std::atan(1.0 / 3.0);  // CoM above the corner
  const auto pgs = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 200;
  {
    World w = tilted_tall_box(balance - 0.05);
    double max_angle = 0;
    for (int s = 0; s < 300; ++s) {
      w.step(*pgs, o, warm_start());
      max_angle = std::max(max_angle, w.bodies().angle[0]);
    }
    EXPECT_LE(max_angle, balance - 0.05 + 1e-9) << "never tips further";
    EXPECT_NEAR(w.bodies().angle[0], 0.0, 0.05) << "falls back onto its base";
  }
  {
    World w = tilted_tall_box(balance + 0.05);
    for (int s = 0; s < 300; ++s) w.step(*pgs, o, warm_start());
    EXPECT_GT(w.bodies().angle[0], 1.2) << "tips over onto its side";
  }
}

TEST(ShapePhysics, TwentyBoxStackStandsTenSeconds) {
  WorldDef d = empty_world(0.5);
  for (int k = 0; k < 20; ++k) d.body.push_back(box({50, 0.5 + k}, {1, 1}));
  World w(d);
  const auto pgs = make_solver("pgs");
  // pgs solves each face's two points as one 2 × 2 LCP (SolverOptions::block_manifolds, as
  // Box2D's block solver): with the builtin warm start 100 sweeps keep the stack straight.
  // Row by row (block_manifolds = false) the same 100 sweeps bias every face's torque the
  // same way and the tower leans by 1 cm in 0.35 s (300 sweeps were needed).
  SolverOptions o;
  o.max_sweeps = 100;
  o.tolerance = 1e-9;
  double drift = 0;
  for (int s = 0; s < 1000; ++s) {
    w.step(*pgs, o, warm_start());
    for (int k = 0; k < 20; ++k) drift = std::max(drift, std::abs(w.bodies().position[static_cast<size_t>(k)].x - 50));
  }
  EXPECT_LT(drift, 0.01);  // 1 % of the width
  EXPECT_NEAR(w.bodies().position[19].y, 19.5, 0.1);
  EXPECT_LT(w.max_penetration(), 0.02);
}

World ellipse_on_floor(double angle) {
  WorldDef d = empty_world(0.8);
  BodyDef e;
  e.shape = BodyShape::Ellipse;
  e.semi_axes = {1.5, 0.5};
  e.angle = angle;
  // Lowest point of the rotated ellipse on the floor.
  const double c = std::cos(angle), s = std::sin(angle);
  e.position = {50, std::sqrt(2.25 * s * s + 0.25 * c * c)};
  d.body.push_back(e);
  return World(d);
}

TEST(ShapePhysics, EllipseOnItsFlatSideIsStableAndOnItsTipFalls) {
  const auto pgs = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 200;
  {
    World w = ellipse_on_floor(0.2);  // tilted from its flat side: rocks back
    for (int s = 0; s < 600; ++s) w.step(*pgs, o, warm_start());
    EXPECT_LT(std::abs(w.bodies().angle[0]), 0.1);
  }
  {
    World w = ellipse_on_floor(0.5 * kPi - 0.01);  // on its tip, slightly off: falls over
    for (int s = 0; s < 300; ++s) w.step(*pgs, o, warm_start());
    EXPECT_LT(w.bodies().angle[0], 0.5 * kPi - 0.8);
  }
}

/// 16 kinematic boxes forming a ring of radius 6 about (20, 20), turning at ω; 12 discs inside.
WorldDef drum(double omega) {
  WorldDef d = empty_world(0.5, {false, false, false, false});
  const Vec2 p{20, 20};
  for (int k = 0; k < 16; ++k) {
    const double phi = 2 * kPi * k / 16;
    BodyDef b = box(p + 6.5 * Vec2{std::cos(phi), std::sin(phi)}, {2.6, 1.0}, phi + 0.5 * kPi, Motion::Kinematic);
    b.omega = omega;
    b.pivot = p;
    d.body.push_back(b);
  }
  for (int k = 0; k < 12; ++k) {
    BodyDef c;
    c.radius = 0.45;
    c.position = p + Vec2{-2.5 + (k % 6), -4.5 + (k / 6)};
    d.body.push_back(c);
  }
  return d;
}

TEST(ShapePhysics, KinematicDrumTurnsThePile) {
  // ω = 0.8 rad/s: Froude number ω² R / g ≈ 0.4, the rolling regime (the pile is carried up the
  // rising side and avalanches down its surface). Measured over the last second: the pile's
  // centre sits on the rising (right) side and its angular momentum about the pivot has the
  // drum's sign; a resting drum keeps it centred and still.
  const auto pgs = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 100;
  const double omega = 0.8;
  double shift[2] = {0, 0}, lz[2] = {0, 0};
  for (const int spin : {0, 1}) {
    World w(drum(spin ? omega : 0.0));
    const int steps = 300, window = 100;
    for (int s = 0; s < steps; ++s) {
      w.step(*pgs, o, warm_start());
      if (s < steps - window) continue;
      for (std::size_t k = 16; k < w.bodies().size(); ++k) {
        const Vec2 r = w.bodies().position[k] - Vec2{20, 20};
        shift[spin] += r.x / (12 * window);
        lz[spin] += w.bodies().mass[k] * cross(r, w.bodies().velocity[k]) / window;
      }
    }
    for (std::size_t k = 16; k < w.bodies().size(); ++k)
      EXPECT_LT(length(w.bodies().position[k] - Vec2{20, 20}), 6.0) << "body " << k << " left the drum";
    // The ring moved as prescribed: still a circle of radius 6.5 about the pivot.
    EXPECT_NEAR(length(w.bodies().position[0] - Vec2{20, 20}), 6.5, 1e-9);
    EXPECT_NEAR(w.bodies().angle[0] - 0.5 * kPi, spin * omega * 3.0, 1e-9);
  }
  EXPECT_NEAR(shift[0], 0.0, 0.3) << "a resting drum keeps the pile centred";
  EXPECT_NEAR(lz[0], 0.0, 0.1);
  EXPECT_GT(shift[1], 0.5) << "a counter-clockwise drum carries the pile up its right side";
  EXPECT_GT(lz[1], 0.0) << "the pile turns with the drum";
}

}  // namespace
}  // namespace dc
