// gate:INNER between builtin and the oracle starters: it keeps builtin against the far negative
// control bad and takes copy's exact λ*.
#include <gtest/gtest.h>
#include <cmath>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "research/research_registry.hpp"
#include "warmstart/floor_discs.hpp"

namespace dc {
namespace {

using test::discs_on_floor;
using test::step_with;

TEST(GateWarmStart, KeepsBuiltinAgainstAWorseGuessAndTakesABetterOne) {
  World w(discs_on_floor({15.0}));
  step_with(w, {3.0});
  w.collide();
  w.assemble();
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  const Eigen::VectorXd b = test::research_registry().make("builtin")->initial_guess(StepView{w});
  ASSERT_GT(natural_residual(w.problem(), b), 1e-6);  // builtin is not the solution

  for (const char* base : {"gate", "gate-l2"}) {
    // bad (λ_n = 50 s) starts further away by either norm: the gate returns builtin exactly.
    const auto keep = test::research_registry().make(std::string(base) + ":bad");
    EXPECT_EQ(keep->name(), std::string(base) + ":bad");
    EXPECT_FALSE(keep->uses_oracle());
    const Eigen::VectorXd g = keep->initial_guess(StepView{w, &star});
    for (int i = 0; i < b.size(); ++i) EXPECT_EQ(g[i], b[i]) << base;
    // copy (λ*) has residual ≈ 0: the gate takes it.
    const auto take = test::research_registry().make(std::string(base) + ":copy");
    EXPECT_TRUE(take->uses_oracle());
    const Eigen::VectorXd h = take->initial_guess(StepView{w, &star});
    for (int i = 0; i < star.size(); ++i) EXPECT_EQ(h[i], star[i]) << base;
  }
}

}  // namespace
}  // namespace dc
