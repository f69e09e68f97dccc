// The oracle diagnostics of builtin's error: copy-range (builtin + the range(A) part of the oracle's
// correction) and copy-active[:F|:normal|:friction] / copy-active-cg against builtin-active.
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "dc/core/error.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "research/research_registry.hpp"
#include "settled_pile.hpp"
#include "warmstart/floor_discs.hpp"

namespace dc {
namespace {

using test::discs_on_floor;
using test::step_with;

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
  const Eigen::VectorXd g = test::research_registry().make("copy-range")->initial_guess(StepView{w, &star});
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
  const Eigen::VectorXd b = test::research_registry().make("builtin")->initial_guess(StepView{w});
  ASSERT_GT((b - star).norm(), 1.0);
  for (const char* spec : {"copy-range", "copy-active", "builtin-active"}) {
    const auto ws = test::research_registry().make(spec);
    EXPECT_EQ(ws->uses_oracle(), std::string(spec) != "builtin-active");
    const Eigen::VectorXd g = ws->initial_guess(StepView{w, &star});
    EXPECT_LT((g - star).norm(), 1e-8 * star.norm()) << spec;
    EXPECT_THROW(test::research_registry().make(std::string(spec) + ":2"), ConfigError);
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
  const Eigen::VectorXd none = test::research_registry().make("builtin-active")->initial_guess(v);
  const Eigen::VectorXd all = test::research_registry().make("copy-active")->initial_guess(v);
  ASSERT_EQ(w.contacts().size(), 2u);
  ASSERT_GT((none - all).norm(), 1.0);  // λ* loads it: the modes differ
  EXPECT_EQ((test::research_registry().make("copy-active:0")->initial_guess(v) - none).norm(), 0.0);
  EXPECT_EQ((test::research_registry().make("copy-active:1")->initial_guess(v) - all).norm(), 0.0);
  EXPECT_EQ(test::research_registry().make("copy-active:0.25")->name(), "copy-active:0.25");
  // The missing load is a normal-mode error (builtin separates what λ* loads): copy-active:normal
  // corrects it like copy-active, copy-active:friction (both must touch) leaves builtin-active's.
  EXPECT_LT((test::research_registry().make("copy-active:normal")->initial_guess(v) - all).norm(), 1e-9 * all.norm());
  EXPECT_EQ((test::research_registry().make("copy-active:friction")->initial_guess(v) - none).norm(), 0.0);
  for (const char* bad : {"copy-active:-0.1", "copy-active:1.5", "copy-active:x", "copy-active:0.5x", "copy-active:Normal"})
    EXPECT_THROW(test::research_registry().make(bad), ConfigError) << bad;
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
    const Eigen::VectorXd dense = test::research_registry().make(base)->initial_guess(v);
    const double few = (test::research_registry().make(std::string(base) + "-cg:3")->initial_guess(v) - dense).norm();
    const double many = (test::research_registry().make(std::string(base) + "-cg:3000")->initial_guess(v) - dense).norm();
    EXPECT_LT(many, 1e-3 * dense.norm()) << base;
    EXPECT_LT(many, few) << base;
    EXPECT_EQ(test::research_registry().make(std::string(base) + "-cg")->name(), std::string(base) + "-cg");
    for (const char* bad : {":0", ":x", ":-3"})
      EXPECT_THROW(test::research_registry().make(std::string(base) + "-cg" + bad), ConfigError) << base << bad;
  }
}

}  // namespace
}  // namespace dc
