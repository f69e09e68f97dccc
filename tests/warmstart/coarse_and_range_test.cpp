// builtin-coarse (a Galerkin coarse-grid gain correction of builtin, no oracle), copy-range
// (builtin + the range(A) part of the oracle's correction, a diagnostic oracle) and the
// active-set starters (copy-active[:F|:normal|:friction], builtin-active, their -cg forms).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "dc/engine/error.hpp"
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

TEST(CopyRangeWarmStart, DropsTheForceRedistributionTheVelocitiesDoNotSee) {
  // A disc in the corner of the floor and the left wall, pushed into it (gravity and an
  // initial velocity towards the wall): four rows (two normals, two frictions) on three
  // degrees of freedom, so A has a null space. The guess keeps λ*'s velocities where the
  // bounds do not bite; it is not λ* itself when λ* − builtin has a null-space part.
  WorldDef d;
  d.bodies.count = 0;
  d.world.walls = {true, false, true, false};
  BodyDef body;
  body.position = {1.0, 1.0};
  body.velocity = {-2.0, -1.0};
  body.radius = 1.0;
  d.body.push_back(body);
  World w(d);
  w.collide();
  w.assemble();
  const LcpProblem& p = w.problem();
  ASSERT_EQ(w.contacts().size(), 2u);
  ASSERT_EQ(p.rows(), 4);
  const Eigen::VectorXd star = solve_oracle(p).lambda;
  const Eigen::VectorXd g = default_warm_starters().make("copy-range")->initial_guess(StepView{w, &star});
  const Eigen::MatrixXd J(p.J);
  const Eigen::MatrixXd A = J * (p.inv_mass * p.dt).asDiagonal() * J.transpose();
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues();
  ASSERT_LT(std::abs(ev[0]), 1e-12 * ev[3]);  // the premise: one null direction
  ASSERT_LT(natural_residual(p, star), 1e-6);
  // The range part of λ* (builtin is 0: δ = λ*) leaves the friction cone; after projection the
  // guess is feasible but neither λ* nor a solution: the null-space part is what made λ*
  // satisfy its bounds.
  Eigen::VectorXd again = g;
  project_feasible(p, again);
  EXPECT_EQ((again - g).norm(), 0.0);
  EXPECT_GT((g - star).norm(), 0.1 * star.norm());
  EXPECT_GT(natural_residual(p, g), 0.1);  // [N]; λ*: < 1e-6
}

TEST(ActiveSetWarmStart, WhereTheSolutionIsUniqueTheDiagnosticsReturnIt) {
  // Separate discs on the floor remembering wrong loads: A is non-singular (δ lies wholly in
  // range(A), copy-range is the oracle) and every contact touches and sticks in λ* and in
  // builtin's memory (both active-set starters solve the LCP).
  World w(discs_on_floor({5.0, 15.0}, 1.0));
  step_with(w, {3.0, 40.0});
  w.collide();
  w.assemble();
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{w});
  ASSERT_GT((b - star).norm(), 1.0);
  for (const char* spec : {"copy-range", "copy-active", "builtin-active"}) {
    const auto ws = default_warm_starters().make(spec);
    EXPECT_EQ(ws->uses_oracle(), std::string(spec) != "builtin-active");
    const Eigen::VectorXd g = ws->initial_guess(StepView{w, &star});
    EXPECT_LT((g - star).norm(), 1e-8 * star.norm()) << spec;
    EXPECT_THROW(default_warm_starters().make(std::string(spec) + ":2"), ConfigError);
  }
}

TEST(ActiveSetWarmStart, APartlyKnownActiveSetSpansBuiltinActiveToCopyActive) {
  // copy-active:0 is builtin-active and copy-active:1 is copy-active, bit for bit; values in
  // between are accepted, values outside [0, 1] are configuration errors.
  World w(discs_on_floor({5.0, 15.0}, 1.0));
  step_with(w, {3.0, 0.0});  // builtin remembers the second disc as unloaded: separating
  w.collide();
  w.assemble();
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  const StepView v{w, &star};
  const Eigen::VectorXd none = default_warm_starters().make("builtin-active")->initial_guess(v);
  const Eigen::VectorXd all = default_warm_starters().make("copy-active")->initial_guess(v);
  ASSERT_EQ(w.contacts().size(), 2u);
  ASSERT_GT((none - all).norm(), 1.0);  // λ* loads it: the modes differ
  EXPECT_EQ((default_warm_starters().make("copy-active:0")->initial_guess(v) - none).norm(), 0.0);
  EXPECT_EQ((default_warm_starters().make("copy-active:1")->initial_guess(v) - all).norm(), 0.0);
  EXPECT_EQ(default_warm_starters().make("copy-active:0.25")->name(), "copy-active:0.25");
  // The missing load is a normal-mode error (builtin separates what λ* loads): copy-active:normal
  // corrects it like copy-active, copy-active:friction (both must touch) leaves builtin-active's.
  EXPECT_LT((default_warm_starters().make("copy-active:normal")->initial_guess(v) - all).norm(), 1e-9 * all.norm());
  EXPECT_EQ((default_warm_starters().make("copy-active:friction")->initial_guess(v) - none).norm(), 0.0);
  for (const char* bad : {"copy-active:-0.1", "copy-active:1.5", "copy-active:x", "copy-active:0.5x", "copy-active:Normal"})
    EXPECT_THROW(default_warm_starters().make(bad), ConfigError) << bad;
}

TEST(ActiveSetWarmStart, TheMatrixFreeSolveTendsToTheDenseOne) {
  // A settling pile of 40 discs (statically indeterminate, so the minimum-norm choice matters):
  // CGLS from builtin's values approaches the dense minimum-norm answer as it iterates, and
  // the -cg names and arguments are checked.
  WorldDef d;
  d.bodies.count = 40;
  d.bodies.seed = 3;
  d.world.width = 12.0;
  World w(d);
  test::step_then_assemble(w, 150, 200);
  ASSERT_GT(w.problem().rows(), 80);
  const Eigen::VectorXd star = solve_oracle(w.problem()).lambda;
  const StepView v{w, &star};
  for (const char* base : {"copy-active", "builtin-active"}) {
    const Eigen::VectorXd dense = default_warm_starters().make(base)->initial_guess(v);
    const double few = (default_warm_starters().make(std::string(base) + "-cg:3")->initial_guess(v) - dense).norm();
    const double many = (default_warm_starters().make(std::string(base) + "-cg:3000")->initial_guess(v) - dense).norm();
    EXPECT_LT(many, 1e-3 * dense.norm()) << base;
    EXPECT_LT(many, few) << base;
    EXPECT_EQ(default_warm_starters().make(std::string(base) + "-cg")->name(), std::string(base) + "-cg");
    for (const char* bad : {":0", ":x", ":-3"})
      EXPECT_THROW(default_warm_starters().make(std::string(base) + "-cg" + bad), ConfigError) << base << bad;
  }
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
