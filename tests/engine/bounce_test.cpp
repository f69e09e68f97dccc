// Analytic tests of normal contact (docs/design.md §8.3): a bounce with restitution e, no bounce below
// the threshold, free fall into a resting contact (λ_n → m g), the speculative row closing
// exactly its gap, Baumgarte pushing a penetrating disc out.
#include <gtest/gtest.h>

#include <cmath>

#include "physics_fixtures.hpp"

namespace dc {
namespace {

using test::kDiscMass;
using test::one_disc;
using test::tight_options;

constexpr std::array<bool, 4> kFloorOnly{false, false, true, false};

struct Bounce {
  double impact_speed = 0;   ///< largest downward speed before the bounce [m/s]
  double rebound_speed = 0;  ///< first upward speed after it [m/s]
  int steps_in_contact = 0;  ///< steps with a contact whose λ_n > 0
  double flight_drift = 0;   ///< |v_y − (rebound − g t)| over the 0.05 s after the bounce [m/s]
};

/// Drops a disc from height `h` above the floor (restitution e) and measures its first impact.
Bounce drop(double h, double e, double dt) {
  WorldDef d = one_disc({100.0, 1.0 + h}, {0.0, 0.0}, {0.0, -9.81}, 0.5, kFloorOnly);
  d.contact.restitution = e;
  d.time.dt = dt;
  World w(d);
  const auto pgs = make_solver("pgs");
  Bounce out;
  const int max_steps = static_cast<int>(std::ceil(3.0 / dt));
  for (int s = 0; s < max_steps; ++s) {
    w.step(*pgs, tight_options());
    for (const Contact& c : w.contacts()) out.steps_in_contact += c.lambda_n > 0 ? 1 : 0;
    const double vy = w.bodies().velocity[0].y;
    if (vy > 1e-6 && out.impact_speed > 0) {
      out.rebound_speed = vy;
      // Then free flight: the contact, still within its margin for a few steps, must not push.
      const int flight = static_cast<int>(std::lround(0.05 / dt));
      for (int f = 1; f <= flight; ++f) {
        w.step(*pgs, tight_options());
        const double expected = out.rebound_speed + f * dt * d.world.gravity.y;
        out.flight_drift = std::max(out.flight_drift, std::abs(w.bodies().velocity[0].y - expected));
      }
      return out;
    }
    out.impact_speed = std::max(out.impact_speed, -vy);
    if (out.steps_in_contact > 3) return out;  // came to rest: no rebound
  }
  return out;
}

TEST(Bounce, ReboundIsRestitutionTimesImpactSpeed) {
  for (double dt : {0.01, 0.001}) {
    for (double e : {0.25, 0.5, 0.8, 1.0}) {
      const Bounce b = drop(4.0, e, dt);
      ASSERT_GT(b.impact_speed, 8.0) << "dt=" << dt << " e=" << e;  // √(2 g 4) ≈ 8.86 m/s
      EXPECT_NEAR(b.rebound_speed, e * b.impact_speed, 0.02 * e * b.impact_speed)
          << "dt=" << dt << " e=" << e;
      EXPECT_LT(b.flight_drift, 1e-9) << "dt=" << dt << " e=" << e;
    }
  }
}

TEST(Bounce, NoReboundWithoutRestitutionOrBelowTheThreshold) {
  for (double dt : {0.01, 0.001}) {
    // e = 0: perfectly inelastic, however fast.
    const Bounce hard = drop(4.0, 0.0, dt);
    EXPECT_GT(hard.impact_speed, 8.0);
    EXPECT_EQ(hard.rebound_speed, 0.0) << "dt=" << dt;
    // e = 0.5 but an approach speed √(2 g 0.03) ≈ 0.77 m/s below the 1 m/s threshold.
    const Bounce soft = drop(0.03, 0.5, dt);
    EXPECT_GT(soft.impact_speed, 0.5);
    EXPECT_LT(soft.impact_speed, 1.0);
    EXPECT_EQ(soft.rebound_speed, 0.0) << "dt=" << dt;
  }
}

TEST(Bounce, HeadOnPairReversesRelativeVelocityTimesE) {
  // Two equal discs, no gravity, closing at 10 m/s: they leave at e·10 m/s, momentum kept.
  for (double e : {0.3, 0.9}) {
    WorldDef d = one_disc({90.0, 100.0}, {5.0, 0.0}, {0.0, 0.0}, 0.5, {false, false, false, false});
    BodyDef other = d.body[0];
    other.position = {110.0, 100.0};
    other.velocity = {-5.0, 0.0};
    d.body.push_back(other);
    d.contact.restitution = e;
    World w(d);
    const auto pgs = make_solver("pgs");
    for (int s = 0; s < 400; ++s) w.step(*pgs, tight_options());
    const Vec2 va = w.bodies().velocity[0], vb = w.bodies().velocity[1];
    EXPECT_NEAR(vb.x - va.x, e * 10.0, 0.02 * e * 10.0) << "e=" << e;
    EXPECT_NEAR(va.x + vb.x, 0.0, 1e-9);
  }
}

TEST(FreeFall, LandsIntoARestingContactCarryingItsWeight) {
  for (double dt : {0.01, 0.001}) {
    WorldDef d = one_disc({100.0, 3.0}, {0.0, 0.0}, {0.0, -9.81}, 0.5, kFloorOnly);
    d.time.dt = dt;
    World w(d);
    const auto pgs = make_solver("pgs");
    double max_up = 0;
    const int steps = static_cast<int>(std::ceil(1.5 / dt));
    for (int s = 0; s < steps; ++s) {
      w.step(*pgs, tight_options());
      max_up = std::max(max_up, w.bodies().velocity[0].y);
    }
    EXPECT_LT(max_up, 1e-6) << "dt=" << dt;  // never moves up: no bounce for e = 0
    ASSERT_EQ(w.contacts().size(), 1u);
    EXPECT_NEAR(w.contacts()[0].lambda_n, kDiscMass * 9.81, 1e-6 * kDiscMass * 9.81);
    EXPECT_NEAR(w.bodies().position[0].y, 1.0, 1e-9);
    EXPECT_NEAR(w.bodies().velocity[0].y, 0.0, 1e-9);
  }
}

TEST(Speculative, AFastDiscEndsTheStepExactlyTouching) {
  // 50 m/s towards the floor, 0.3 m above it: a free step would move 0.5 m (tunnelling half
  // the radius). The speculative row lets it close exactly the gap, then stops it.
  for (double mu : {0.0, 0.5}) {
    World w(one_disc({100.0, 1.3}, {0.0, -50.0}, {0.0, 0.0}, mu, kFloorOnly));
    const auto pgs = make_solver("pgs");
    w.step(*pgs, tight_options());
    ASSERT_EQ(w.contacts().size(), 1u);
    EXPECT_NEAR(w.contacts()[0].gap, 0.3, 1e-12);
    EXPECT_NEAR(w.bodies().position[0].y, 1.0, 1e-9) << "mu=" << mu;
    EXPECT_NEAR(w.bodies().velocity[0].y, -0.3 / w.def().time.dt, 1e-7);
    w.step(*pgs, tight_options());
    EXPECT_NEAR(w.bodies().position[0].y, 1.0, 1e-9);
    EXPECT_NEAR(w.bodies().velocity[0].y, 0.0, 1e-7);
  }
}

TEST(Speculative, ADistantDiscIsNotHeldBack) {
  // Gap 0.6 m, free step 0.5 m: the contact exists but its row must not act.
  World w(one_disc({100.0, 1.6}, {0.0, -50.0}, {0.0, 0.0}, 0.5, kFloorOnly));
  const auto pgs = make_solver("pgs");
  w.step(*pgs, tight_options());
  ASSERT_EQ(w.contacts().size(), 1u);
  EXPECT_EQ(w.contacts()[0].lambda_n, 0.0);
  EXPECT_NEAR(w.bodies().position[0].y, 1.1, 1e-12);
}

TEST(Baumgarte, APenetratingDiscIsPushedOutAtRateBeta) {
  // One step removes the fraction β of the penetration beyond the slop (no gravity); the disc
  // then leaves with that velocity and never goes deeper.
  World w = test::world_unchecked(one_disc({100.0, 0.9}, {0.0, 0.0}, {0.0, 0.0}, 0.5, kFloorOnly));
  const auto pgs = make_solver("pgs");
  const ContactSection& cs = w.def().contact;
  const double excess = 0.1 - cs.slop;
  w.step(*pgs, tight_options());
  EXPECT_NEAR(1.0 - w.bodies().position[0].y - cs.slop, (1.0 - cs.baumgarte) * excess, 1e-9);
  EXPECT_NEAR(w.bodies().velocity[0].y, cs.baumgarte * excess / w.def().time.dt, 1e-7);
  double y = w.bodies().position[0].y;
  for (int s = 0; s < 20; ++s) {
    w.step(*pgs, tight_options());
    EXPECT_GE(w.bodies().position[0].y, y) << "step " << s;
    y = w.bodies().position[0].y;
  }
  EXPECT_GT(y, 1.0 - cs.slop);
}

}  // namespace
}  // namespace dc
