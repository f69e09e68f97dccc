// sph-gain / sph-gain-add: the oracle bounds of a multiplicative grid correction of builtin,
// λ⁰ = λ_prev (1 + ĝ(p)) with ĝ = bilinear(Σ W δ λp) / bilinear(Σ W λp²) (+ the remainder's
// Shepard read-back for sph-gain-add).
#include <gtest/gtest.h>

#include <cmath>

#include "dc/core/error.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "floor_discs.hpp"

namespace dc {
namespace {

using test::discs_on_floor;
using test::step_with;

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
