// sph-residual (builtin + the grid read-back of λ* − builtin: the oracle bound of a residual
// grid predictor) and gate:INNER (per step INNER's guess or builtin's, whichever has the
// smaller natural-map residual).
#include <gtest/gtest.h>

#include <cmath>

#include "dc/engine/error.hpp"
#include "dc/engine/lcp_problem.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "floor_discs.hpp"

namespace dc {
namespace {

using test::discs_on_floor;
using test::step_with;

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
