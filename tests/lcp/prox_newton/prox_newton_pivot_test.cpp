// prox-newton's pivoting finish (solvers/prox_newton/pivot_finish.hpp): Lemke on the split LCP
// of a contact problem against newton (same contact velocities), its size rule, and the solver
// reaching the target through it when the passes and the proximal finish are cut short; the
// proximal-point route's stall limit.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "dc/lcp/proximal_point.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/pivot_finish.hpp"

namespace dc {
namespace {

double velocity_gap(const LcpProblem& p, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (lcp_velocity(p, a) - lcp_velocity(p, b)).cwiseAbs().maxCoeff();
}

TEST(ProxNewtonPivot, SplitLcpSizeCountsThreeUnknownsPerFrictionRow) {
  test::TestRng rng(7);
  const LcpProblem p = test::random_contact(10, 12, true, rng, 0.5, 3);  // every 3rd frictionless
  int normal = 0, friction = 0;
  for (int i = 0; i < p.rows(); ++i) (p.is_friction_row(i) ? friction : normal) += 1;
  EXPECT_EQ(solvers::prox::pivot_lcp_size(p), normal + 3 * friction);
  LcpProblem general = p;
  general.lo[0] = -INFINITY;  // a bilateral row: not a contact problem
  EXPECT_EQ(solvers::prox::pivot_lcp_size(general), -1);
  EXPECT_FALSE(solvers::prox::pivot_solve(general).lambda.has_value());
}

TEST(ProxNewtonPivot, SameContactVelocitiesAsNewton) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed + 900);
    const LcpProblem c = test::without_jacobian(test::random_contact(12, 30, true, rng, 0.5, 4));
    const SolveResult ref = make_solver("newton")->solve(c, {}, test::capped_options(3000));
    ASSERT_EQ(ref.status, SolveStatus::Converged) << ref.message;
    const solvers::prox::PivotOutcome po = solvers::prox::pivot_solve(c);
    ASSERT_TRUE(po.lambda.has_value()) << po.why;
    const double scale = std::max(1.0, c.b.lpNorm<Eigen::Infinity>());
    EXPECT_LE(natural_residual(c, *po.lambda), 1e-8 * scale) << "seed " << seed;
    EXPECT_LE(velocity_gap(c, ref.lambda, *po.lambda), 1e-6) << "seed " << seed;
  }
}

// Passes, proximal finish and safeguard cut to nothing: where Lemke ends on a solution (it can
// also end on a ray of a solvable problem), the pivoting finish alone reaches the hard target and
// the message names it; without it the same solve does not converge.
TEST(ProxNewtonPivot, ReachesTheTargetWhenTheOtherPartsAreCutShort) {
  ProxNewtonDef d;
  d.max_outer = 1;
  d.inner_iterations = 1;
  d.finish_iterations = 0;
  d.proximal_finish = false;
  d.safeguard_sweeps = 0;
  d.local_pivot_rows = 0;
  ProxNewtonDef without = d;
  without.pivot_rows = 0;
  int pivoted = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed + 950);
    const LcpProblem c = test::without_jacobian(test::random_contact(15, 40, true, rng));
    const SolveResult cut = ProxNewtonSolver(without).solve(c, {}, test::capped_options());
    ASSERT_NE(cut.status, SolveStatus::Converged) << "seed " << seed << ": too easy a problem";
    if (!solvers::prox::pivot_solve(c).lambda) continue;
    ++pivoted;
    const SolveResult r = ProxNewtonSolver(d).solve(c, {}, test::capped_options());
    EXPECT_EQ(r.status, SolveStatus::Converged) << "seed " << seed << ": " << r.message;
    EXPECT_NE(r.message.find("lemke pivoting finish"), std::string::npos) << r.message;
  }
  EXPECT_GE(pivoted, 2);
}

TEST(ProxNewtonPivot, FromTheSolutionNeedsNoPivot) {
  test::TestRng rng(977);
  const LcpProblem c = test::without_jacobian(test::random_contact(12, 30, true, rng));
  const SolveResult ref = make_solver("newton")->solve(c, {}, test::capped_options(3000));
  ASSERT_EQ(ref.status, SolveStatus::Converged) << ref.message;
  ProxNewtonSolver s;
  const SolveResult r = s.solve(c, ref.lambda, test::capped_options());
  EXPECT_EQ(r.status, SolveStatus::Converged) << r.message;
  EXPECT_EQ(s.last_stats().pivots, 0);
}

TEST(ProximalPointStalls, NegativeLimitIsRejectedAndALargeOneChangesNothing) {
  test::TestRng rng(31);
  const LcpProblem c = test::without_jacobian(test::random_contact(15, 30, true, rng));
  ProximalPointDef bad;
  bad.max_stalls = -1;
  EXPECT_THROW((void)solve_proximal_point(c, {}, test::capped_options(), bad), InvalidArgument);
  ProximalPointDef limited;
  limited.max_stalls = 1000;
  const SolveResult a = solve_proximal_point(c, {}, test::capped_options(), ProximalPointDef{});
  const SolveResult b = solve_proximal_point(c, {}, test::capped_options(), limited);
  EXPECT_EQ(a.status, b.status);
  EXPECT_TRUE(a.lambda == b.lambda);
}

// One stalled outer iteration allowed: the route stops early and says why.
TEST(ProximalPointStalls, StopsAfterTheLimitAndSaysSo) {
  test::TestRng rng(33);
  const LcpProblem c = test::without_jacobian(test::random_contact(15, 30, true, rng));
  ProximalPointDef d;
  d.max_stalls = 1;
  d.inner_iterations = 1;  // inner solves too short to improve every outer iteration
  SolverOptions o = test::capped_options();
  o.tolerance = 1e-300;  // unreachable: only the stall limit or max_outer stops the route
  const SolveResult r = solve_proximal_point(c, {}, o, d);
  EXPECT_NE(r.status, SolveStatus::Converged);
  EXPECT_NE(r.message.find("without a new best residual"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace dc
