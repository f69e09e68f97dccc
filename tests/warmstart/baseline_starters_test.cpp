// The two non-learned baselines (docs/bench.md): builtin-extrapolate (linear extrapolation of each
// contact's λ over its last two steps, clamped to the cone) and builtin-statics (builtin plus
// a top-down static load guess for contacts without history).
#include <gtest/gtest.h>

#include <cmath>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {
namespace {

/// One unit disc resting exactly on the floor (gap 0), floor only.
WorldDef one_disc() {
  WorldDef d;
  d.bodies.count = 0;
  d.world.walls = {false, false, true, false};
  BodyDef b;
  b.position = {15.0, 1.0};
  d.body.push_back(b);
  return d;
}

/// Solves nothing: stores λ = (ln, lt) for the single contact and puts the disc back at rest,
/// so the next step has the same contact (same key) with the chosen history.
void step_with(World& w, double ln, double lt) {
  w.collide();
  w.assemble();
  ASSERT_EQ(w.contacts().size(), 1u);
  w.integrate(w.pack({ln}, {lt}));
  w.bodies().position[0] = {15.0, 1.0};
  w.bodies().velocity[0] = {0.0, 0.0};
  w.bodies().omega[0] = 0.0;
}

TEST(ExtrapolateWarmStart, LinearHistoryIsExtrapolatedExactly) {
  World w(one_disc());
  const auto ws = default_warm_starters().make("builtin-extrapolate");
  step_with(w, 3.0, 0.5);  // λ at step 0
  w.collide();
  w.assemble();
  // Only one step of history: builtin's guess.
  Eigen::VectorXd g = ws->initial_guess(StepView{w});
  EXPECT_DOUBLE_EQ(g[w.normal_row(0)], 3.0);
  EXPECT_DOUBLE_EQ(g[w.tangent_row(0)], 0.5);
  step_with(w, 4.0, 0.75);  // λ at step 1 (the line λ(s) = 3 + s, 0.5 + 0.25 s)
  w.collide();
  w.assemble();
  g = ws->initial_guess(StepView{w});
  EXPECT_DOUBLE_EQ(g[w.normal_row(0)], 5.0);
  EXPECT_DOUBLE_EQ(g[w.tangent_row(0)], 1.0);
}

TEST(ExtrapolateWarmStart, ExtrapolationIsClampedToTheFrictionCone) {
  World w(one_disc());
  const auto ws = default_warm_starters().make("builtin-extrapolate");
  step_with(w, 4.0, 0.0);
  w.collide();
  w.assemble();
  (void)ws->initial_guess(StepView{w});
  step_with(w, 1.0, 0.4);  // 2·1 − 4 = −2 < 0: λ_n clamps to 0, and λ_t with it
  w.collide();
  w.assemble();
  Eigen::VectorXd g = ws->initial_guess(StepView{w});
  EXPECT_EQ(g[w.normal_row(0)], 0.0);
  EXPECT_EQ(g[w.tangent_row(0)], 0.0);

  // A rising λ_n with a fast-growing λ_t: |λ_t| is clamped to μ λ_n.
  World v(one_disc());
  const auto ws2 = default_warm_starters().make("builtin-extrapolate");
  step_with(v, 1.0, 0.0);
  v.collide();
  v.assemble();
  (void)ws2->initial_guess(StepView{v});
  step_with(v, 2.0, 1.0);  // → (3, 2), μ = 0.5: λ_t = 1.5
  v.collide();
  v.assemble();
  g = ws2->initial_guess(StepView{v});
  EXPECT_DOUBLE_EQ(g[v.normal_row(0)], 3.0);
  EXPECT_DOUBLE_EQ(g[v.tangent_row(0)], 0.5 * 3.0);
}

TEST(ExtrapolateWarmStart, ForgetsHistoryWhenTheStepDoesNotAdvanceByOne) {
  World w(one_disc());
  const auto ws = default_warm_starters().make("builtin-extrapolate");
  step_with(w, 3.0, 0.0);
  w.collide();
  w.assemble();
  (void)ws->initial_guess(StepView{w});
  step_with(w, 4.0, 0.0);
  step_with(w, 6.0, 0.0);  // a step the starter did not see
  w.collide();
  w.assemble();
  const Eigen::VectorXd g = ws->initial_guess(StepView{w});
  EXPECT_DOUBLE_EQ(g[w.normal_row(0)], 6.0);  // builtin, not 2·6 − 3
}

/// A column of `n` unit discs exactly touching each other and the floor.
World column(int n, double density = 1.0) {
  WorldDef d;
  d.bodies.count = 0;
  d.world.walls = {false, false, true, false};
  for (int k = 0; k < n; ++k) {
    BodyDef b;
    b.position = {15.0, 1.0 + 2.0 * k};
    b.density = density;
    d.body.push_back(b);
  }
  World w(d);
  w.collide();
  w.assemble();
  return w;
}

TEST(StaticsGuess, RestingColumnCarriesTheCumulativeWeightAsAForce) {
  const int n = 6;
  World w = column(n, 2.0);
  const double weight = w.bodies().mass[0] * 9.81;  // every disc alike
  ASSERT_EQ(static_cast<int>(w.contacts().size()), n);
  const Eigen::VectorXd g = statics_guess(w);
  // λ is a force [N] here (docs/design.md §2): contact under disc k carries the weight of discs k..n−1.
  for (std::size_t c = 0; c < w.contacts().size(); ++c) {
    const Contact& k = w.contacts()[c];
    const int below_top = n - k.body_b;  // discs resting on this contact (b is the upper body)
    EXPECT_NEAR(g[w.normal_row(static_cast<int>(c))], below_top * weight, 1e-9 * n * weight) << c;
    EXPECT_EQ(g[w.tangent_row(static_cast<int>(c))], 0.0);
  }
  // … which is this step's exact LCP solution (a static column): the units agree with λ*.
  const OracleSolution os = solve_oracle(w.problem());
  for (int c = 0; c < n; ++c)
    EXPECT_NEAR(g[w.normal_row(c)], os.lambda[w.normal_row(c)], 1e-6 * n * weight) << c;
}

TEST(StaticsGuess, SlantedSupportsBalanceTheWeightVertically) {
  // Disc 2 rests on discs 0 and 1 (which rest on the floor), its centre √3 above theirs.
  WorldDef d;
  d.bodies.count = 0;
  d.world.walls = {false, false, true, false};
  for (const Vec2 x : {Vec2{14.0, 1.0}, Vec2{16.0, 1.0}, Vec2{15.0, 1.0 + std::sqrt(3.0) + 1e-9}}) {
    BodyDef b;
    b.position = x;
    d.body.push_back(b);
  }
  World w(d);
  w.collide();
  w.assemble();
  const Eigen::VectorXd g = statics_guess(w);
  const double m = w.bodies().mass[0], gn = 9.81;
  double vertical_on_top = 0, floor_total = 0;
  for (std::size_t c = 0; c < w.contacts().size(); ++c) {
    const Contact& k = w.contacts()[c];
    const double lam = g[w.normal_row(static_cast<int>(c))];
    if (k.body_a < 0) floor_total += lam;
    else if (k.body_b == 2 || k.body_a == 2) vertical_on_top += lam * std::abs(k.normal.y);
  }
  EXPECT_NEAR(vertical_on_top, m * gn, 1e-9);
  EXPECT_NEAR(floor_total, 3 * m * gn, 1e-9);  // the floor carries everything
}

TEST(StaticsWarmStart, KeepsBuiltinForContactsWithHistory) {
  World w = column(3);
  w.integrate(w.pack({7.0, 8.0, 9.0}, {0.0, 0.0, 0.0}));  // some history, not the statics
  for (int k = 0; k < 3; ++k) {
    w.bodies().position[static_cast<std::size_t>(k)] = {15.0, 1.0 + 2.0 * k};
    w.bodies().velocity[static_cast<std::size_t>(k)] = {0.0, 0.0};
  }
  // A fourth disc appears on top: its contact is new.
  w.bodies().add({15.0, 7.0}, 1.0, 1.0);
  w.collide();
  w.assemble();
  ASSERT_EQ(w.contacts().size(), 4u);
  const auto ws = default_warm_starters().make("builtin-statics");
  const Eigen::VectorXd g = ws->initial_guess(StepView{w});
  const Eigen::VectorXd s = statics_guess(w);
  for (int c = 0; c < 4; ++c) {
    const Contact& k = w.contacts()[static_cast<std::size_t>(c)];
    if (k.body_b == 3) {
      EXPECT_DOUBLE_EQ(g[w.normal_row(c)], s[w.normal_row(c)]);  // new: statics
      EXPECT_NEAR(g[w.normal_row(c)], w.bodies().mass[3] * 9.81, 1e-9);
    } else {
      EXPECT_EQ(g[w.normal_row(c)], w.previous_contacts()[static_cast<std::size_t>(c)].lambda_n);  // builtin
    }
  }
}

}  // namespace
}  // namespace dc
