// The grid oracles: sph-residual (builtin + the grid read-back of this step's correction),
// sph-gain and sph-gain-add (builtin × a grid gain field of the correction, + the remainder).
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

TEST(SphResidualWarmStart, IsolatedContactsGetBuiltinPlusTheExactCorrection) {
  // Two discs 10 m apart: each contact is alone under its grid kernel, so the Shepard round
  // trip of its correction is exact and builtin + (λ* − builtin) = λ*, whatever builtin was.
  World w(discs_on_floor({5.0, 15.0}));
  step_with(w, {3.0, 40.0});
  w.collide();
  w.assemble();
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  const auto builtin = test::research_registry().make("builtin");
  const Eigen::VectorXd b = builtin->initial_guess(StepView{w});
  ASSERT_EQ(b[w.normal_row(0)], 3.0);
  ASSERT_GT(std::abs(star[w.normal_row(0)] - 3.0), 1.0);  // builtin is wrong on both
  ASSERT_GT(std::abs(star[w.normal_row(1)] - 40.0), 1.0);
  const auto ws = test::research_registry().make("sph-residual:poly6:0.5:0.5");
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
  const Eigen::VectorXd b = test::research_registry().make("builtin")->initial_guess(StepView{w});
  const Eigen::VectorXd g = test::research_registry().make("sph-residual")->initial_guess(StepView{w, &b});
  ASSERT_EQ(g.size(), b.size());
  for (int i = 0; i < b.size(); ++i) EXPECT_EQ(g[i], b[i]) << "row " << i;
}

TEST(SphGainWarmStart, IsolatedContactsGetTheExactLambdaStar) {
  // Alone under its kernel a contact's least-squares gain is δ/λp: λp (1 + ĝ) = λ*.
  World w(discs_on_floor({5.0, 15.0}, 1.0));
  step_with(w, {3.0, 40.0});
  w.collide();
  w.assemble();
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  ASSERT_GT(std::abs(star[w.normal_row(0)] - 3.0), 1.0);
  ASSERT_GT(std::abs(star[w.normal_row(1)] - 40.0), 1.0);
  for (const char* spec : {"sph-gain:poly6:0.5:0.5", "sph-gain-add:poly6:0.5:0.5"}) {
    const auto ws = test::research_registry().make(spec);
    EXPECT_EQ(ws->name(), spec);
    EXPECT_TRUE(ws->uses_oracle());
    const Eigen::VectorXd g = ws->initial_guess(StepView{w, &star});
    for (int k = 0; k < 2; ++k) EXPECT_NEAR(g[w.normal_row(k)], star[w.normal_row(k)], 1e-9 * star.norm()) << spec;
  }
}

TEST(SphGainWarmStart, AUniformScaleComesBackExactlyWhereAnAdditiveGridBlursIt) {
  // Kernels overlap (contacts 0.7 m apart, h = 2 m) and the "oracle" is 1.5 × builtin: the gain
  // field is 0.5 everywhere, so sph-gain returns it exactly; sph-residual's additive grid
  // mixes the three corrections (0.5·2, 0.5·5, 0.5·7) and misses each.
  World w(discs_on_floor({10.0, 10.7, 11.4}, 0.3));
  step_with(w, {2.0, 5.0, 7.0});
  w.collide();
  w.assemble();
  const Eigen::VectorXd b = test::research_registry().make("builtin")->initial_guess(StepView{w});
  const Eigen::VectorXd star = 1.5 * b;
  const Eigen::VectorXd g = test::research_registry().make("sph-gain:poly6:1:2")->initial_guess(StepView{w, &star});
  const Eigen::VectorXd r = test::research_registry().make("sph-residual:poly6:1:2")->initial_guess(StepView{w, &star});
  double miss = 0;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(g[w.normal_row(k)], star[w.normal_row(k)], 1e-12 * star.norm()) << "contact " << k;
    miss = std::max(miss, std::abs(r[w.normal_row(k)] - star[w.normal_row(k)]));
  }
  EXPECT_GT(miss, 0.1);
}

TEST(SphGainWarmStart, NewContactsNeedTheAdditiveRemainder) {
  // No history: λp = 0, no gain can reach λ*; sph-gain keeps builtin's 0, sph-gain-add's
  // remainder read-back is exact for an isolated contact.
  World w(discs_on_floor({5.0}, 1.0));
  w.collide();
  w.assemble();
  ASSERT_TRUE(w.previous_contacts().empty());
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  ASSERT_GT(star[w.normal_row(0)], 1.0);
  const Eigen::VectorXd g = test::research_registry().make("sph-gain")->initial_guess(StepView{w, &star});
  const Eigen::VectorXd a = test::research_registry().make("sph-gain-add")->initial_guess(StepView{w, &star});
  EXPECT_EQ(g[w.normal_row(0)], 0.0);
  EXPECT_NEAR(a[w.normal_row(0)], star[w.normal_row(0)], 1e-9 * star.norm());
  EXPECT_THROW(test::research_registry().make("sph-gain:poly6:-1:1"), ConfigError);
}

}  // namespace
}  // namespace dc
