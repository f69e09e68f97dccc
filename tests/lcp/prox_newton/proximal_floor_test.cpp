// The proximal-point route's failure floor of δ across calls and its stall limit there
// (ProximalPointDef::initial_floor, floor_stalls; ProxNewtonDef::guess_route_from_floor): δ_0
// never lies below the floor given, the route reports the floor it ended with, a stalled route
// at a raised floor stops early at a prefix of the unlimited route and says so, and with these
// settings the answers keep lemke's contact velocities on small frictional problems.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <string>

#include "dc/core/error.hpp"
#include "dc/lcp/fc2d_dat_file.hpp"
#include "dc/lcp/fc2d_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "dc/lcp/proximal_point.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/pivot_finish.hpp"

namespace dc {
namespace {

const std::string kData = std::string(DC_SOURCE_DIR) + "/tests/data/fc2d/";

LcpProblem assembled(LcpProblem p) {
  p.ensure_assembled_matrix();
  return test::without_jacobian(p);
}

ProximalPointDef floored() {
  ProximalPointDef d;
  d.initial_floor = 1e-4;
  d.floor_stalls = 3;
  d.newton_sparse.fallback_cap_fall = 0.5;
  return d;
}

TEST(ProximalPointFloor, KeepsLemkesContactVelocities) {
  for (const bool friction : {true, false}) {
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      test::TestRng rng(seed + 3300);
      const LcpProblem p = assembled(test::random_contact(20, 25, friction, rng, 0.5, friction ? 3 : 0));
      const auto po = solvers::prox::pivot_solve(p);
      ASSERT_TRUE(po.lambda.has_value()) << po.why;
      SolverOptions o;
      ProximalPointStats ps;
      const SolveResult r = solve_proximal_point(p, Eigen::VectorXd(), o, floored(), &ps);
      const std::string what = std::string(friction ? "friction" : "frictionless") + " seed " + std::to_string(seed);
      EXPECT_EQ(r.status, SolveStatus::Converged) << what << ": " << r.message;
      EXPECT_GE(ps.floor, 1e-4) << what << ": the floor never falls with floor_decay 1";
      EXPECT_LE((lcp_velocity(p, r.lambda) - lcp_velocity(p, *po.lambda)).cwiseAbs().maxCoeff(), 1e-6) << what;
      ProxNewtonDef pd;
      pd.guess_route_from_floor = true;
      pd.finish_route = floored();
      const SolveResult q = make_prox_newton(pd)->solve(p, Eigen::VectorXd(), o);
      EXPECT_EQ(q.status, SolveStatus::Converged) << what << ": " << q.message;
      EXPECT_LE((lcp_velocity(p, q.lambda) - lcp_velocity(p, *po.lambda)).cwiseAbs().maxCoeff(), 1e-6) << what;
    }
  }
}

TEST(ProximalPointFloor, FirstShiftIsNeverBelowTheInitialFloor) {
  // One outer iteration at δ_0: a floor above initial_shift makes it the floor's shift.
  const LcpProblem p = fc2d_to_lcp(read_fc2d_dat(kData + "fc2d_granularflowonwall_02020_00213.dat").problem);
  SolverOptions o;
  ProximalPointDef at_floor;
  at_floor.max_outer = 1;
  at_floor.initial_floor = 1e-3;
  ProximalPointDef at_shift;
  at_shift.max_outer = 1;
  at_shift.initial_shift = 1e-3;
  ProximalPointStats ps;
  const SolveResult a = solve_proximal_point(p, Eigen::VectorXd(), o, at_floor, &ps);
  const SolveResult b = solve_proximal_point(p, Eigen::VectorXd(), o, at_shift);
  EXPECT_EQ(a.lambda, b.lambda);
  EXPECT_EQ(a.sweeps, b.sweeps);
  EXPECT_GE(ps.floor, 1e-3);
  // A floor at or below min_shift is the default route, bit for bit, to the same answer.
  ProximalPointDef low;
  low.initial_floor = low.min_shift;
  const SolveResult c = solve_proximal_point(p, Eigen::VectorXd(), o);
  const SolveResult d = solve_proximal_point(p, Eigen::VectorXd(), o, low);
  ASSERT_EQ(c.status, SolveStatus::Converged) << c.message;
  EXPECT_EQ(c.lambda, d.lambda);
  EXPECT_EQ(c.sweeps, d.sweeps);
  // A raised floor still reaches the default route's contact velocities on a resting pile.
  const LcpProblem pile = assembled(test::deep_pile(6, 6, 0.5));
  ProximalPointDef high;
  high.initial_floor = 1e-4;
  const SolveResult e = solve_proximal_point(pile, Eigen::VectorXd(), o);
  const SolveResult f = solve_proximal_point(pile, Eigen::VectorXd(), o, high);
  ASSERT_EQ(e.status, SolveStatus::Converged) << e.message;
  ASSERT_EQ(f.status, SolveStatus::Converged) << f.message;
  const Eigen::VectorXd we = pile.A * e.lambda + pile.b, wf = pile.A * f.lambda + pile.b;
  EXPECT_LE((we - wf).lpNorm<Eigen::Infinity>(), 1e-6 * std::max(1.0, pile.b.lpNorm<Eigen::Infinity>()));
}

TEST(ProximalPointFloor, StallsAtARaisedFloorStopEarlyAndSaySo) {
  // An unreachable target at the largest shift: passes at the floor stop finding new bests once
  // the centre reaches round-off. The limited route is a prefix of the unlimited one.
  const LcpProblem p = assembled(test::deep_pile(6, 6, 0.5));
  SolverOptions o;
  o.tolerance = 1e-300;
  ProximalPointDef full;
  full.initial_floor = full.max_shift;
  full.max_outer = 60;
  ProximalPointDef limited = full;
  limited.floor_stalls = 3;
  const SolveResult a = solve_proximal_point(p, Eigen::VectorXd(), o, full);
  const SolveResult b = solve_proximal_point(p, Eigen::VectorXd(), o, limited);
  EXPECT_NE(b.status, SolveStatus::Converged);
  EXPECT_NE(b.message.find("stalled"), std::string::npos) << b.message;
  EXPECT_LT(b.sweeps, a.sweeps);
  EXPECT_LE(a.residual, b.residual);
  EXPECT_EQ(b.residual, natural_residual(p, b.lambda));
}

TEST(ProximalPointFloor, RefusesInvalidSettings) {
  test::TestRng rng(3);
  const LcpProblem p = test::without_jacobian(test::random_contact(6, 10, true, rng));
  SolverOptions o;
  ProximalPointDef bad;
  bad.initial_floor = -1;
  EXPECT_THROW(solve_proximal_point(p, Eigen::VectorXd(), o, bad), InvalidArgument);
  bad = {};
  bad.floor_stalls = -1;
  EXPECT_THROW(solve_proximal_point(p, Eigen::VectorXd(), o, bad), InvalidArgument);
}

}  // namespace
}  // namespace dc
