// sph-residual (builtin + the grid read-back of λ* − builtin: the oracle bound of a residual
// grid predictor) and gate:INNER (per step INNER's guess or builtin's, whichever has the
// smaller natural-map residual).
#include <gtest/gtest.h>

#include <cmath>

#include "dc/engine/error.hpp"
#include "dc/engine/lcp_problem.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {
namespace {

/// Discs of radius r resting exactly on the floor (gap 0) at the given x, floor only.
WorldDef discs_on_floor(std::initializer_list<double> xs, double r = 1.0) {
  WorldDef d;
  d.bodies.count = 0;
  d.world.walls = {false, false, true, false};
  for (const double x : xs) {
    BodyDef b;
    b.position = {x, r};
    b.radius = r;
    d.body.push_back(b);
  }
  return d;
}

/// Stores the given λ_n (λ_t = 0) as the solved λ of each disc's floor contact and puts the
/// discs back at rest, so the next step has the same contacts (same keys) with that history.
void step_with(World& w, const std::vector<double>& ln) {
  w.collide();
  w.assemble();
  ASSERT_EQ(w.contacts().size(), ln.size());
  const std::vector<Vec2> at(w.bodies().position.begin(), w.bodies().position.end());
  w.integrate(w.pack(ln, std::vector<double>(ln.size(), 0.0)));
  for (std::size_t i = 0; i < at.size(); ++i) {
    w.bodies().position[i] = at[i];
    w.bodies().velocity[i] = {0.0, 0.0};
    w.bodies().omega[i] = 0.0;
  }
}

TEST(SphResidualWarmStart, IsolatedContactsGetBuiltinPlusTheExactCorrection) {
  // Two discs 10 m apart: each contact is alone under its grid kernel, so the Shepard round
  // trip of its correction is exact and builtin + (λ* − builtin) = λ*, whatever builtin was.
  World w(discs_on_floor({5.0, 15.0}));
  step_with(w, {3.0, 40.0});
  w.collide();
  w.assemble();
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  const auto builtin = default_warm_starters().make("builtin");
  const Eigen::VectorXd b = builtin->initial_guess(StepView{w});
  ASSERT_EQ(b[w.normal_row(0)], 3.0);
  ASSERT_GT(std::abs(star[w.normal_row(0)] - 3.0), 1.0);  // builtin is wrong on both
  ASSERT_GT(std::abs(star[w.normal_row(1)] - 40.0), 1.0);
  const auto ws = default_warm_starters().make("sph-residual:poly6:0.5:0.5");
  EXPECT_EQ(ws->name(), "sph-residual:poly6:0.5:0.5");
  EXPECT_TRUE(ws->uses_oracle());
  const Eigen::VectorXd g = ws->initial_guess(StepView{w, &star});
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(g[w.normal_row(k)], star[w.normal_row(k)], 1e-9 * star.norm());
}

TEST(SphResidualWarmStart, NoCorrectionLeavesBuiltinUntouched) {
  // When the oracle equals builtin's memory the correction grid is zero: builtin, bit-equal,
  // even for contacts close enough to share grid nodes.
  World w(discs_on_floor({10.0, 10.7, 11.4}, 0.3));  // 0.1 m apart: kernels overlap
  step_with(w, {2.0, 5.0, 7.0});
  w.collide();
  w.assemble();
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{w});
  const Eigen::VectorXd g = default_warm_starters().make("sph-residual")->initial_guess(StepView{w, &b});
  ASSERT_EQ(g.size(), b.size());
  for (int i = 0; i < b.size(); ++i) EXPECT_EQ(g[i], b[i]) << "row " << i;
}

TEST(GateWarmStart, KeepsBuiltinAgainstAWorseGuessAndTakesABetterOne) {
  World w(discs_on_floor({15.0}));
  step_with(w, {3.0});
  w.collide();
  w.assemble();
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{w});
  ASSERT_GT(natural_residual(w.problem(), b), 1e-6);  // builtin is not the solution

  for (const char* base : {"gate", "gate-l2"}) {
    // bad (λ_n = 50 s) starts further away by either norm: the gate returns builtin exactly.
    const auto keep = default_warm_starters().make(std::string(base) + ":bad");
    EXPECT_EQ(keep->name(), std::string(base) + ":bad");
    EXPECT_FALSE(keep->uses_oracle());
    const Eigen::VectorXd g = keep->initial_guess(StepView{w, &star});
    for (int i = 0; i < b.size(); ++i) EXPECT_EQ(g[i], b[i]) << base;
    // copy (λ*) has residual ≈ 0: the gate takes it.
    const auto take = default_warm_starters().make(std::string(base) + ":copy");
    EXPECT_TRUE(take->uses_oracle());
    const Eigen::VectorXd h = take->initial_guess(StepView{w, &star});
    for (int i = 0; i < star.size(); ++i) EXPECT_EQ(h[i], star[i]) << base;
  }
}

TEST(GateWarmStart, BadSpecificationsAreOneLineErrors) {
  const WarmStarterRegistry r = default_warm_starters();
  EXPECT_THROW(r.make("gate"), ConfigError);                // nothing to gate
  EXPECT_THROW(r.make("gate:gate:copy"), ConfigError);      // no gate of a gate
  EXPECT_THROW(r.make("gate-l2:nonsense"), ConfigError);    // unknown inner starter
  EXPECT_THROW(r.make("gate:copy:x"), ConfigError);         // the inner's own argument check
  EXPECT_NO_THROW(r.make("gate:builtin-statics"));
}

}  // namespace
}  // namespace dc
