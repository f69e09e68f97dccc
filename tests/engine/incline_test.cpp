// Analytic tests of Coulomb friction on a disc (I = ½ m r²): tilted gravity on the floor makes
// an incline of angle θ; gravity into a side wall with a vertical component makes a wall the
// disc rolls or slides down.
//   rolling (μ ≥ tan θ / 3):  a = ⅔ g sin θ, ω = −v/r, friction f = ⅓ m g sin θ
//   sliding (μ < tan θ / 3):  a = g (sin θ − μ cos θ), α = 2 μ g cos θ / r, f = μ m g cos θ
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "physics_fixtures.hpp"

namespace dc {
namespace {

using test::kDiscMass;
using test::one_disc;
using test::tight_options;

constexpr double kG = 9.81;
constexpr double kTheta = 20.0 * std::numbers::pi / 180.0;  // tan θ / 3 ≈ 0.121

/// The floor as an incline: gravity rotated by θ, so "downhill" is +x.
WorldDef incline(double mu, double dt) {
  WorldDef d = one_disc({100.0, 1.0}, {0.0, 0.0}, {kG * std::sin(kTheta), -kG * std::cos(kTheta)},
                        mu, {false, false, true, false});
  d.time.dt = dt;
  return d;
}

TEST(Incline, RollsWithTwoThirdsGSinThetaAndNoSlip) {
  for (double dt : {0.01, 0.001}) {
    World w(incline(0.5, dt));
    const auto pgs = make_solver("pgs");
    const int steps = static_cast<int>(std::lround(1.0 / dt));
    for (int s = 0; s < steps; ++s) {
      w.step(*pgs, tight_options());
      const Vec2 v = w.bodies().velocity[0];
      // The contact point does not slip after any step (the LCP holds it exactly).
      ASSERT_NEAR(v.x + w.bodies().omega[0] * 1.0, 0.0, 1e-9) << "dt=" << dt << " step " << s;
      ASSERT_NEAR(v.y, 0.0, 1e-9);
      ASSERT_EQ(w.contacts().size(), 1u);
      // t = perp(0, 1) = (−1, 0): λ_t > 0 is a force uphill.
      EXPECT_NEAR(w.contacts()[0].lambda_t, kDiscMass * kG * std::sin(kTheta) / 3.0, 1e-6 * kDiscMass * kG);
    }
    const double t = steps * dt;
    const double a = w.bodies().velocity[0].x / t;
    EXPECT_NEAR(a, 2.0 / 3.0 * kG * std::sin(kTheta), 0.02 * 2.0 / 3.0 * kG * std::sin(kTheta))
        << "dt=" << dt;
    EXPECT_NEAR(w.bodies().omega[0], -w.bodies().velocity[0].x / 1.0, 0.02 * std::abs(w.bodies().omega[0]));
    EXPECT_NEAR(w.contacts()[0].lambda_n, kDiscMass * kG * std::cos(kTheta), 1e-6 * kDiscMass * kG);
  }
}

TEST(Incline, SlidesWithGSinThetaMinusMuGCosThetaAndSpinsUp) {
  const double mu = 0.05;  // < tan θ / 3
  for (double dt : {0.01, 0.001}) {
    World w(incline(mu, dt));
    const auto pgs = make_solver("pgs");
    const int steps = static_cast<int>(std::lround(1.0 / dt));
    for (int s = 0; s < steps; ++s) w.step(*pgs, tight_options());
    const double t = steps * dt;
    const double a = w.bodies().velocity[0].x / t;
    const double alpha = w.bodies().omega[0] / t;
    const double a_exact = kG * (std::sin(kTheta) - mu * std::cos(kTheta));
    const double alpha_exact = -2.0 * mu * kG * std::cos(kTheta) / 1.0;  // clockwise
    EXPECT_NEAR(a, a_exact, 0.02 * a_exact) << "dt=" << dt;
    EXPECT_NEAR(alpha, alpha_exact, 0.02 * std::abs(alpha_exact)) << "dt=" << dt;
    ASSERT_EQ(w.contacts().size(), 1u);
    const Contact& c = w.contacts()[0];
    EXPECT_NEAR(c.lambda_n, kDiscMass * kG * std::cos(kTheta), 1e-6 * kDiscMass * kG);
    EXPECT_NEAR(std::abs(c.lambda_t), mu * c.lambda_n, 1e-9 * c.lambda_n);  // on the cone
  }
}

/// A disc against the left wall, pressed into it by g_x = −10 m/s², falling with g_y = −5 m/s².
WorldDef side_wall(double mu) {
  return one_disc({1.0, 150.0}, {0.0, 0.0}, {-10.0, -5.0}, mu, {true, false, false, false});
}

TEST(SideWall, SlidingFrictionIsMuTimesTheWallForce) {
  const double mu = 0.1;  // μ g_x = 1 < g_y / 3: slides
  World w(side_wall(mu));
  const auto pgs = make_solver("pgs");
  for (int s = 0; s < 100; ++s) {
    w.step(*pgs, tight_options());
    ASSERT_EQ(w.contacts().size(), 1u);
    const Contact& c = w.contacts()[0];
    EXPECT_NEAR(c.lambda_n, kDiscMass * 10.0, 1e-6 * kDiscMass * 10.0) << "step " << s;
    // t = perp(1, 0) = (0, 1): friction points up, against the fall, from the first step on.
    EXPECT_NEAR(c.lambda_t, mu * c.lambda_n, 1e-9 * c.lambda_n) << "step " << s;
  }
  const double a = -w.bodies().velocity[0].y / (100 * w.def().time.dt);
  EXPECT_NEAR(a, 5.0 - mu * 10.0, 0.02 * (5.0 - mu * 10.0));
  EXPECT_NEAR(w.bodies().position[0].x, 1.0, 1e-9);
}

TEST(SideWall, RollsDownTheWallWithoutSlipWhenMuIsLarge) {
  const double mu = 1.0;  // μ g_x = 10 > g_y / 3
  World w(side_wall(mu));
  const auto pgs = make_solver("pgs");
  for (int s = 0; s < 100; ++s) {
    w.step(*pgs, tight_options());
    ASSERT_EQ(w.contacts().size(), 1u);
    // Contact point offset r = (−1, 0) from the centre, ω × r = (0, −ω): the slip is v_y − ω.
    ASSERT_NEAR(w.bodies().velocity[0].y - w.bodies().omega[0], 0.0, 1e-9) << "step " << s;
    EXPECT_NEAR(w.contacts()[0].lambda_t, kDiscMass * 5.0 / 3.0, 1e-6 * kDiscMass) << "step " << s;
  }
  const double a = -w.bodies().velocity[0].y / (100 * w.def().time.dt);
  EXPECT_NEAR(a, 2.0 / 3.0 * 5.0, 0.02 * 2.0 / 3.0 * 5.0);
}

}  // namespace
}  // namespace dc
