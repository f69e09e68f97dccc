// builtin-coarse (a Galerkin coarse-grid gain correction of builtin, no oracle), copy-range
// (builtin + the range(A) part of the oracle's correction, a diagnostic oracle) and the
// active-set starters (copy-active[:F|:normal|:friction], builtin-active, their -cg forms).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "dc/core/error.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "floor_discs.hpp"
#include "settled_pile.hpp"

namespace dc {
namespace {

using test::discs_on_floor;
using test::step_with;

/// E(λ) = ½ λᵀAλ + bᵀλ, the energy whose minimum over the coarse space builtin-coarse finds.
double energy(const LcpProblem& p, const Eigen::VectorXd& l) {
  const Eigen::VectorXd w = lcp_velocity(p, l);  // A λ + b
  return 0.5 * l.dot(w - p.b) + p.b.dot(l);
}

TEST(CoarseWarmStart, AUniformlyWrongLoadIsCorrectedExactlyByOneGainNode) {
  // Separate discs on the floor (A diagonal, all rows interior at λ*) remembering half of
  // their load: λ* = λ_b (1 + 1) lies in the coarse space of a one-node grid (D larger than
  // the box), and it is the energy minimum there, so the correction is exact.
  World w(discs_on_floor({5.0, 12.0, 20.0}, 1.0));
  w.collide();
  w.assemble();
  const Eigen::VectorXd star0 = solve_oracle(w.problem()).lambda;
  std::vector<double> half;
  for (int k = 0; k < 3; ++k) half.push_back(0.5 * star0[w.normal_row(k)]);
  step_with(w, half);
  w.collide();
  w.assemble();
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  const auto ws = default_warm_starters().make("builtin-coarse:100:5");
  EXPECT_EQ(ws->name(), "builtin-coarse:100:5");
  EXPECT_FALSE(ws->uses_oracle());
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{w});
  const Eigen::VectorXd g = ws->initial_guess(StepView{w});
  for (int k = 0; k < 3; ++k) {
    ASSERT_NEAR(b[w.normal_row(k)], 0.5 * star[w.normal_row(k)], 1e-6 * star.norm());
    EXPECT_NEAR(g[w.normal_row(k)], star[w.normal_row(k)], 1e-6 * star.norm()) << "contact " << k;
  }
}

TEST(CoarseWarmStart, LowersTheEnergyAndTheResidualOfAMixedError) {
  // Loads remembered 0.3×, 1.6× and 0.9× too small/large on a 1 m grid: the correction cannot
  // be exact (one smooth field, three ratios) but it lowers the energy it minimises.
  World w(discs_on_floor({10.0, 11.0, 12.0}, 0.4));
  w.collide();
  w.assemble();
  const Eigen::VectorXd star0 = solve_oracle(w.problem()).lambda;
  const double f[3] = {0.3, 1.6, 0.9};
  std::vector<double> hist;
  for (int k = 0; k < 3; ++k) hist.push_back(f[k] * star0[w.normal_row(k)]);
  step_with(w, hist);
  w.collide();
  w.assemble();
  const LcpProblem& p = w.problem();
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{w});
  const Eigen::VectorXd g = default_warm_starters().make("builtin-coarse:1:50")->initial_guess(StepView{w});
  EXPECT_LT(energy(p, g), energy(p, b) - 1e-9 * std::abs(energy(p, b)));
  EXPECT_LT(natural_residual_l2(p, g), natural_residual_l2(p, b));
  for (int i = 0; i < g.size(); ++i) EXPECT_TRUE(std::isfinite(g[i]));
}

TEST(CoarseWarmStart, ContactsWithoutHistoryKeepBuiltinsZero) {
  World w(discs_on_floor({5.0, 15.0}, 1.0));
  w.collide();
  w.assemble();
  ASSERT_TRUE(w.previous_contacts().empty());
  const Eigen::VectorXd g = default_warm_starters().make("builtin-coarse")->initial_guess(StepView{w});
  EXPECT_EQ(g.size(), w.problem().rows());
  EXPECT_EQ(g.norm(), 0.0);
}

TEST(CoarseWarmStart, RejectsBadSettings) {
  for (const char* bad : {"builtin-coarse:0", "builtin-coarse:-1", "builtin-coarse:x", "builtin-coarse:1:0",
                          "builtin-coarse:1:2:3", "builtin-coarse:1x", "builtin-coarse:inf"})
    EXPECT_THROW(default_warm_starters().make(bad), ConfigError) << bad;
  EXPECT_NO_THROW(default_warm_starters().make("builtin-coarse:0.5:10"));
}

TEST(ActiveSetWarmStart, ANewContactThatIsAwayIsLeftSeparating) {
  // No history, the disc 0.5 m above the floor: builtin-active calls its contact separating
  // (if the narrow phase reports it at all) and returns zeros.
  World w(discs_on_floor({5.0}, 1.0));
  w.bodies().position[0].y = 1.5;
  w.collide();
  w.assemble();
  const Eigen::VectorXd g = default_warm_starters().make("builtin-active")->initial_guess(StepView{w});
  EXPECT_EQ(g.size(), w.problem().rows());
  EXPECT_EQ(g.norm(), 0.0);
}

}  // namespace
}  // namespace dc
