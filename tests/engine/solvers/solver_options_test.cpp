// solver_options (lcp_solver.hpp): a scene's [solver] section → SolverOptions, and the
// options do what the section says when a solver runs with them.
#include <gtest/gtest.h>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world_def.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

TEST(SolverOptionsFromScene, CopiesSweepsToleranceOmegaAndKeepsTheRestAtDefaults) {
  const WorldDef d = parse_scene("[solver]\nname = \"psor\"\nsweeps = 77\ntolerance = 1e-7\nomega = 1.3\n");
  const SolverOptions o = solver_options(d.solver);
  EXPECT_EQ(o.max_sweeps, 77);
  EXPECT_EQ(o.tolerance, 1e-7);
  EXPECT_EQ(o.omega, 1.3);
  const SolverOptions defaults;
  EXPECT_EQ(o.record_theta, defaults.record_theta);
  EXPECT_EQ(o.exact_tolerance, defaults.exact_tolerance);
  EXPECT_EQ(o.block_manifolds, defaults.block_manifolds);
  EXPECT_TRUE(o.checkpoints.empty());
  EXPECT_FALSE(o.on_checkpoint);
  // The default section gives the seed's fixed 3000 sweeps, no tolerance, plain PGS.
  const SolverOptions seed = solver_options(SolverSection{});
  EXPECT_EQ(seed.max_sweeps, SolverSection{}.sweeps);
  EXPECT_EQ(seed.tolerance, 0.0);
  EXPECT_EQ(seed.omega, 1.0);
}

TEST(SolverOptionsFromScene, SolversObeyTheSection) {
  test::TestRng rng(7);
  const LcpProblem p = test::random_contact(20, 40, true, rng);
  SolverSection s;
  s.name = SolverId{SolverKind::Psor};
  s.sweeps = 9;  // fixed-sweep mode: exactly `sweeps` sweeps
  const auto solver = make_solver(s.name);
  const SolveResult capped = solver->solve(p, Eigen::VectorXd(), solver_options(s));
  EXPECT_EQ(capped.sweeps, 9);
  EXPECT_EQ(capped.status, SolveStatus::SweepLimit);

  s.sweeps = 20000;  // tolerance mode: stops at the first θ_k ≤ tolerance
  s.tolerance = 1e-8;
  const SolveResult tol = solver->solve(p, Eigen::VectorXd(), solver_options(s));
  ASSERT_EQ(tol.status, SolveStatus::Converged);
  ASSERT_FALSE(tol.theta.empty());
  EXPECT_LE(tol.theta.back(), 1e-8);
  EXPECT_LT(tol.sweeps, 20000);

  // omega reaches psor: over-relaxation changes the iterates of the first sweeps.
  s.sweeps = 3;
  s.tolerance = 0;
  const SolveResult plain = solver->solve(p, Eigen::VectorXd(), solver_options(s));
  s.omega = 1.5;
  const SolveResult relaxed = solver->solve(p, Eigen::VectorXd(), solver_options(s));
  EXPECT_GT((plain.lambda - relaxed.lambda).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace dc
