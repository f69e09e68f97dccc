// The default route of `lcp solve` (dc/lcp/default_route.hpp): chosen by the kind of problem;
// prox-newton first, the plain Newton and the proximal route taking over where it does not
// reach the solution test.
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

TEST(DefaultRoute, AFrictionalProblemIsSolvedByProxNewton) {
  const ProblemFile f = read_problem_file(kData + "fc2d/FrictionContactProblem00071.dat");
  ASSERT_FALSE(is_standard_lcp(f.lcp));
  const RouteResult r = solve_with_default_route(f.lcp);
  EXPECT_EQ(r.route, "prox-newton");
  EXPECT_EQ(r.solver, "prox-newton");
  EXPECT_EQ(r.result.status, SolveStatus::Converged) << r.result.message;
  EXPECT_LE(r.result.residual, solution_target(f.lcp, SolverOptions{}));
}

TEST(DefaultRoute, LaterStagesTakeOverWhereProxNewtonStops) {
  // One Newton iteration (max_sweeps) and its nncg safeguard cannot solve Siconos' 2020-contact
  // granular file (W indefinite after its 6-digit print), nor can one plain newton-sparse
  // iteration: the proximal-point route (its own limits) passes the solution test. Every run
  // counts in `sweeps`, and the message says, stage by stage, why each stopped.
  const ProblemFile f = read_problem_file(kData + "fc2d/fc2d_granularflowonwall_02020_00213.dat");
  SolverOptions one;
  one.max_sweeps = 1;
  DefaultRouteDef def;
  const RouteResult r = solve_with_default_route(f.lcp, one, def);
  EXPECT_EQ(r.route, "prox-newton then newton-sparse then proximal:newton-sparse");
  EXPECT_EQ(r.solver, "proximal:newton-sparse");
  EXPECT_EQ(r.result.status, SolveStatus::Converged) << r.result.message;
  EXPECT_LE(r.result.residual, solution_target(f.lcp, SolverOptions{}));
  EXPECT_GT(r.result.sweeps, 2);
  EXPECT_EQ(r.result.message.rfind("prox-newton: sweep_limit", 0), 0u) << r.result.message;
  EXPECT_NE(r.result.message.find("; newton-sparse: sweep_limit"), std::string::npos) << r.result.message;
  def.proximal = false;
  const RouteResult q = solve_with_default_route(f.lcp, one, def);
  EXPECT_EQ(q.route, "prox-newton");
  EXPECT_EQ(q.result.status, SolveStatus::SweepLimit);
  // Without the plain run (--proximal): prox-newton, then the proximal-point route. 00727 is
  // solved by prox-newton alone.
  def.proximal = true;
  def.plain = false;
  const ProblemFile g = read_problem_file(kData + "fc2d/FrictionContactProblem00727.dat");
  const RouteResult p = solve_with_default_route(g.lcp, SolverOptions{}, def);
  EXPECT_EQ(p.route, "prox-newton");
  EXPECT_EQ(p.result.status, SolveStatus::Converged) << p.result.message;
}

}  // namespace
}  // namespace dc
