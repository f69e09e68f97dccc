// The default route of `lcp solve` (dc/lcp/default_route.hpp): chosen by the kind of problem,
// the proximal route taking over where the plain Newton does not reach the solution test.
#include <gtest/gtest.h>

#include <string>

#include "dc/lcp/default_route.hpp"
#include "dc/lcp/problem_file.hpp"

namespace dc {
namespace {

const std::string kData = std::string(DC_SOURCE_DIR) + "/tests/data/";

TEST(DefaultRoute, AStandardLcpIsSolvedByLemke) {
  const ProblemFile f = read_problem_file(kData + "lcp/contact_12.dat");
  ASSERT_TRUE(is_standard_lcp(f.lcp));
  const RouteResult r = solve_with_default_route(f.lcp);
  EXPECT_EQ(r.route, "lemke");
  EXPECT_EQ(r.solver, "lemke");
  EXPECT_EQ(r.result.status, SolveStatus::Converged) << r.result.message;
  const SolveResult named = make_solver("lemke")->solve(f.lcp, Eigen::VectorXd(), SolverOptions{});
  EXPECT_EQ(r.result.lambda, named.lambda);
}

TEST(DefaultRoute, AFrictionalProblemIsSolvedByNewtonSparse) {
  const ProblemFile f = read_problem_file(kData + "fc2d/FrictionContactProblem00071.dat");
  ASSERT_FALSE(is_standard_lcp(f.lcp));
  const RouteResult r = solve_with_default_route(f.lcp);
  EXPECT_EQ(r.route, "newton-sparse");
  EXPECT_EQ(r.result.status, SolveStatus::Converged) << r.result.message;
  EXPECT_LE(r.result.residual, solution_target(f.lcp, SolverOptions{}));
}

TEST(DefaultRoute, ProxNewtonTakesOverWhereThePlainRunStops) {
  // Two plain iterations cannot solve 00727: prox-newton takes over and passes the solution
  // test; both runs count in `sweeps`, and the message says why the plain run stopped.
  const ProblemFile f = read_problem_file(kData + "fc2d/FrictionContactProblem00727.dat");
  DefaultRouteDef def;
  def.plain_iterations = 2;
  const RouteResult r = solve_with_default_route(f.lcp, SolverOptions{}, def);
  EXPECT_EQ(r.route, "newton-sparse then prox-newton");
  EXPECT_EQ(r.solver, "prox-newton");
  EXPECT_EQ(r.result.status, SolveStatus::Converged) << r.result.message;
  EXPECT_LE(r.result.residual, solution_target(f.lcp, SolverOptions{}));
  EXPECT_GT(r.result.sweeps, 2);
  EXPECT_EQ(r.result.message.rfind("newton-sparse: sweep_limit", 0), 0u) << r.result.message;
  def.plain = false;
  const RouteResult p = solve_with_default_route(f.lcp, SolverOptions{}, def);
  EXPECT_EQ(p.route, "prox-newton");
  EXPECT_EQ(p.result.status, SolveStatus::Converged) << p.result.message;
  def.plain = true;
  def.proximal = false;
  const RouteResult q = solve_with_default_route(f.lcp, SolverOptions{}, def);
  EXPECT_EQ(q.route, "newton-sparse");
  EXPECT_EQ(q.result.status, SolveStatus::SweepLimit);
}

}  // namespace
}  // namespace dc
