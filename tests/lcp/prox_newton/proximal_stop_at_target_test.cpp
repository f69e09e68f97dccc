// The proximal-point route's stop at the original problem's target inside an inner solve
// (ProximalPointDef::stop_at_target, NewtonSparseDef::stop_when): the route's iterates are
// those without it up to the first inner iterate at the target, which it returns; it never
// takes more inner iterations, and on a deep pile with a loose target fewer; its answers have
// lemke's contact velocities on small frictional problems.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/proximal_point.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/pivot_finish.hpp"

namespace dc {
namespace {

LcpProblem assembled(LcpProblem p) {
  p.ensure_assembled_matrix();
  return test::without_jacobian(p);
}

TEST(NewtonSparseStopWhen, EndsTheSolveAtTheCallersIteration) {
  const LcpProblem p = assembled(test::deep_pile(6, 6, 0.5));
  SolverOptions o;
  const SolveResult free_run = make_newton_sparse()->solve(p, Eigen::VectorXd(), o);
  ASSERT_GT(free_run.sweeps, 2) << free_run.message;
  NewtonSparseDef d;
  int calls = 0;
  d.stop_when = [&calls](int it, const Eigen::VectorXd&) {
    ++calls;
    return it >= 2;
  };
  NewtonSparseSolver solver(d);
  const SolveResult r = solver.solve(p, Eigen::VectorXd(), o);
  EXPECT_EQ(r.sweeps, 2);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(solver.last_stats().iterations, 2);
  EXPECT_NE(r.status, SolveStatus::Converged);
}

TEST(ProximalPoint, StopsAtTheFirstInnerIterateAtTheTarget) {
  // A 40-layer resting pile from zero with a loose target (1e-6 of a body's weight): the first
  // inner solve passes the original problem's target long before its own, tighter one.
  const LcpProblem p = assembled(test::deep_pile(12, 40, 0.5));
  SolverOptions o;
  o.tolerance = 1e-6 * M_PI * 9.81;
  ProximalPointDef off;
  off.stop_at_target = false;
  const SolveResult a = solve_proximal_point(p, Eigen::VectorXd(), o);
  const SolveResult b = solve_proximal_point(p, Eigen::VectorXd(), o, off);
  ASSERT_LE(b.residual, o.tolerance) << b.message;
  EXPECT_LE(a.residual, o.tolerance) << a.message;
  EXPECT_EQ(a.residual, natural_residual(p, a.lambda));
  EXPECT_LT(a.sweeps, b.sweeps);
  // Loose targets only move the stop: every route stops at its own target, never later.
  for (const double scale : {1e-4, 1e-8}) {
    SolverOptions t = o;
    t.tolerance = scale * M_PI * 9.81;
    const SolveResult on = solve_proximal_point(p, Eigen::VectorXd(), t);
    const SolveResult without = solve_proximal_point(p, Eigen::VectorXd(), t, off);
    if (without.residual > t.tolerance) continue;
    EXPECT_LE(on.residual, t.tolerance) << scale;
    EXPECT_LE(on.sweeps, without.sweeps) << scale;
  }
}

TEST(ProximalPoint, StopAtTargetKeepsLemkesContactVelocities) {
  for (const bool friction : {true, false}) {
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      test::TestRng rng(seed + 3100);
      const LcpProblem p = assembled(test::random_contact(20, 25, friction, rng, 0.5, friction ? 3 : 0));
      const auto po = solvers::prox::pivot_solve(p);
      ASSERT_TRUE(po.lambda.has_value()) << po.why;
      SolverOptions o;
      const SolveResult r = solve_proximal_point(p, Eigen::VectorXd(), o);
      const std::string what = std::string(friction ? "friction" : "frictionless") + " seed " + std::to_string(seed);
      EXPECT_EQ(r.status, SolveStatus::Converged) << what << ": " << r.message;
      EXPECT_LE((lcp_velocity(p, r.lambda) - lcp_velocity(p, *po.lambda)).cwiseAbs().maxCoeff(), 1e-6) << what;
    }
  }
}

}  // namespace
}  // namespace dc
