// sph-gain / sph-gain-add: the oracle bounds of a multiplicative grid correction of builtin,
// λ⁰ = λ_prev (1 + ĝ(p)) with ĝ = bilinear(Σ W δ λp) / bilinear(Σ W λp²) (+ the remainder's
// Shepard read-back for sph-gain-add).
#include <gtest/gtest.h>

#include <cmath>

#include "dc/engine/error.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "floor_discs.hpp"

namespace dc {
namespace {

using test::discs_on_floor;
using test::step_with;

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
    const auto ws = default_warm_starters().make(spec);
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
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{w});
  const Eigen::VectorXd star = 1.5 * b;
  const Eigen::VectorXd g = default_warm_starters().make("sph-gain:poly6:1:2")->initial_guess(StepView{w, &star});
  const Eigen::VectorXd r = default_warm_starters().make("sph-residual:poly6:1:2")->initial_guess(StepView{w, &star});
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
  const Eigen::VectorXd g = default_warm_starters().make("sph-gain")->initial_guess(StepView{w, &star});
  const Eigen::VectorXd a = default_warm_starters().make("sph-gain-add")->initial_guess(StepView{w, &star});
  EXPECT_EQ(g[w.normal_row(0)], 0.0);
  EXPECT_NEAR(a[w.normal_row(0)], star[w.normal_row(0)], 1e-9 * star.norm());
  EXPECT_THROW(default_warm_starters().make("sph-gain:poly6:-1:1"), ConfigError);
}

// builtin-gain-extrapolate: the smoothed gain of the change t−2 → t−1 applied once more. Loads
// that all grow by 10 % per step (a uniform gain field) come back grown by 10 % again; a
// starter that did not see the previous step (no t−2 memory) is plain builtin.
TEST(GainExtrapolateWarmStart, AUniformLoadRampIsContinued) {
  World w(discs_on_floor({10.0, 10.7, 11.4}, 0.3));
  const auto ws = default_warm_starters().make("builtin-gain-extrapolate:poly6:1:2");
  EXPECT_EQ(ws->name(), "builtin-gain-extrapolate:poly6:1:2");
  EXPECT_FALSE(ws->uses_oracle());
  const std::vector<double> l1 = {2.0, 5.0, 7.0}, l2 = {2.2, 5.5, 7.7};
  for (const std::vector<double>* l : {&l1, &l2}) {
    w.collide();
    w.assemble();
    (void)ws->initial_guess(StepView{w});  // remembers this step's previous contacts
    test::integrate_and_rest(w, *l);
  }
  w.collide();
  w.assemble();
  ASSERT_EQ(w.contacts().size(), 3u);
  const Eigen::VectorXd g = ws->initial_guess(StepView{w});
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(g[w.normal_row(k)], 1.1 * l2[static_cast<std::size_t>(k)], 1e-9) << "contact " << k;
  const Eigen::VectorXd fresh =
      default_warm_starters().make("builtin-gain-extrapolate:poly6:1:2")->initial_guess(StepView{w});
  EXPECT_EQ(fresh, default_warm_starters().make("builtin")->initial_guess(StepView{w}));
  EXPECT_THROW(default_warm_starters().make("builtin-gain-extrapolate:poly6:0:1"), ConfigError);
}

}  // namespace
}  // namespace dc
