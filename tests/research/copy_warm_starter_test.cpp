// copy and copy:D: this step's oracle λ*, shared by the bench or solved here, and rounded.
#include <gtest/gtest.h>
#include <cmath>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "research/research_registry.hpp"
#include "warmstart/three_discs.hpp"

namespace dc {
namespace {

using test::three_discs_next_step;

TEST(CopyWarmStart, ReturnsTheSharedOracleOrSolvesItAccurately) {
  const World w = three_discs_next_step();
  const LcpProblem& p = w.problem();
  const auto copy = test::research_registry().make("copy");
  EXPECT_TRUE(copy->uses_oracle());
  Eigen::VectorXd shared = Eigen::VectorXd::Constant(p.rows(), 0.125);
  EXPECT_EQ(copy->initial_guess(StepView{w, &shared}), shared);  // shared oracle used as is
  EXPECT_EQ(copy->oracle_ms(), 0.0);
  const Eigen::VectorXd own = copy->initial_guess(StepView{w});
  EXPECT_LE(natural_residual(p, own), 1e-8);
}

TEST(CopyWarmStart, DecimalsRoundTheOracle) {
  const World w = three_discs_next_step();
  const LcpProblem& p = w.problem();
  const Eigen::VectorXd star = solve_oracle(p).lambda;
  for (int d : {0, 1, 3}) {
    const auto copy = test::research_registry().make("copy:" + std::to_string(d));
    EXPECT_EQ(copy->name(), "copy:" + std::to_string(d));
    const Eigen::VectorXd g = copy->initial_guess(StepView{w, &star});
    const double scale = std::pow(10.0, d);
    for (int i = 0; i < p.rows(); ++i) {
      EXPECT_LE(std::abs(g[i] - star[i]), 0.5 / scale + 1e-12) << "copy:" << d << " row " << i;
      EXPECT_GE(g[i], p.lower(i, g));
      EXPECT_LE(g[i], p.upper(i, g));
      if (!p.is_friction_row(i)) {
        EXPECT_NEAR(g[i] * scale, std::round(g[i] * scale), 1e-6) << "copy:" << d;
      }
    }
  }
  for (const char* bad : {"copy:x", "copy:-1", "copy:16", "copy:2.5"})
    EXPECT_THROW(test::research_registry().make(bad), ConfigError) << bad;
}

}  // namespace
}  // namespace dc
