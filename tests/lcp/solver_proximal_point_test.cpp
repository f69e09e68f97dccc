// The proximal-point route (dc/lcp/proximal_point.hpp): it must reach the exact tolerance
// on Siconos' 2020-contact granular file, whose W (printed with six digits) is indefinite,
// agree with newton-sparse where both converge, and refuse invalid settings and guesses.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/fc2d_dat_file.hpp"
#include "dc/lcp/fc2d_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/proximal_point.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

using namespace test;

const std::string kData = std::string(DC_SOURCE_DIR) + "/tests/data/fc2d/";

double exact_bound(const LcpProblem& p) { return 1e-9 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()); }

TEST(ProximalPoint, SolvesTheIndefiniteGranular2020File) {
  const LcpProblem p = fc2d_to_lcp(read_fc2d_dat(kData + "fc2d_granularflowonwall_02020_00213.dat").problem);
  SolverOptions o;
  const SolveResult r = solve_proximal_point(p, Eigen::VectorXd(), o);
  EXPECT_EQ(r.status, SolveStatus::Converged) << r.message;
  EXPECT_LE(natural_residual(p, r.lambda), exact_bound(p));
  EXPECT_EQ(r.residual, natural_residual(p, r.lambda));
}

TEST(ProximalPoint, AgreesWithNewtonSparseOnAPile) {
  // A resting pile has more contact rows than degrees of freedom (A singular): reactions need
  // not be unique, velocities w = A λ + b are (A positive semidefinite).
  LcpProblem p = deep_pile(6, 6, 0.5);
  p.ensure_assembled_matrix();
  p = without_jacobian(p);
  SolverOptions o;
  const SolveResult a = solve_proximal_point(p, Eigen::VectorXd(), o);
  const SolveResult b = make_solver("newton-sparse")->solve(p, Eigen::VectorXd(), o);
  ASSERT_EQ(a.status, SolveStatus::Converged) << a.message;
  ASSERT_EQ(b.status, SolveStatus::Converged) << b.message;
  EXPECT_LE(natural_residual(p, a.lambda), exact_bound(p));
  const Eigen::VectorXd wa = p.A * a.lambda + p.b, wb = p.A * b.lambda + p.b;
  EXPECT_LE((wa - wb).lpNorm<Eigen::Infinity>(), 1e-6 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()));
}

TEST(ProximalPoint, InexactInnerSolvesReachTheSameTarget) {
  // ProximalPointDef::inner_forcing loosens only the inner solves: the route still stops on the
  // original problem's residual, and the velocities agree with the exact-inner route.
  const LcpProblem p = fc2d_to_lcp(read_fc2d_dat(kData + "fc2d_granularflowonwall_02020_00213.dat").problem);
  SolverOptions o;
  ProximalPointDef inexact;
  inexact.inner_forcing = 0.1;
  const SolveResult a = solve_proximal_point(p, Eigen::VectorXd(), o);
  const SolveResult b = solve_proximal_point(p, Eigen::VectorXd(), o, inexact);
  ASSERT_EQ(a.status, SolveStatus::Converged) << a.message;
  ASSERT_EQ(b.status, SolveStatus::Converged) << b.message;
  EXPECT_LE(natural_residual(p, b.lambda), exact_bound(p));
  const Eigen::VectorXd wa = p.A * a.lambda + p.b, wb = p.A * b.lambda + p.b;
  EXPECT_LE((wa - wb).lpNorm<Eigen::Infinity>(), 1e-6 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()));
}

TEST(ProximalPoint, RerunIsBitEqual) {
  TestRng rng(7);
  LcpProblem p = random_contact(12, 30, true, rng);
  p.ensure_assembled_matrix();
  SolverOptions o;
  const SolveResult a = solve_proximal_point(p, Eigen::VectorXd(), o);
  const SolveResult b = solve_proximal_point(p, Eigen::VectorXd(), o);
  EXPECT_EQ(a.lambda, b.lambda);
  EXPECT_EQ(a.sweeps, b.sweeps);
}

TEST(ProximalPoint, CheckpointsSeeTheBestIterateInOrderAndTheAnswerLast) {
  const LcpProblem p = fc2d_to_lcp(read_fc2d_dat(kData + "fc2d_granularflowonwall_02020_00213.dat").problem);
  SolverOptions o;
  for (int k = 1; k <= 2000; ++k) o.checkpoints.push_back(k);
  std::vector<int> seen;
  Eigen::VectorXd last;
  o.on_checkpoint = [&](int k, const Eigen::VectorXd& lambda) {
    seen.push_back(k);
    last = lambda;
  };
  const SolveResult r = solve_proximal_point(p, Eigen::VectorXd(), o);
  ASSERT_EQ(r.status, SolveStatus::Converged) << r.message;
  ASSERT_GT(seen.size(), 1u);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_LT(seen[i - 1], seen[i]);
  EXPECT_EQ(seen.back(), 2000) << "a converged solve passes the rest of the checkpoints its answer";
  EXPECT_EQ(last, r.lambda);
}

TEST(ProximalPoint, FloorDecayReachesTheSameVelocities) {
  // ProximalPointDef::floor_decay lets δ fall below a failed shift again: the route still stops
  // on the original problem's residual, at the velocities of the default route.
  const LcpProblem p = fc2d_to_lcp(read_fc2d_dat(kData + "fc2d_granularflowonwall_02020_00213.dat").problem);
  SolverOptions o;
  ProximalPointDef decay;
  decay.floor_decay = 10;
  const SolveResult a = solve_proximal_point(p, Eigen::VectorXd(), o);
  const SolveResult b = solve_proximal_point(p, Eigen::VectorXd(), o, decay);
  ASSERT_EQ(a.status, SolveStatus::Converged) << a.message;
  ASSERT_EQ(b.status, SolveStatus::Converged) << b.message;
  EXPECT_LE(natural_residual(p, b.lambda), exact_bound(p));
  const Eigen::VectorXd wa = p.A * a.lambda + p.b, wb = p.A * b.lambda + p.b;
  EXPECT_LE((wa - wb).lpNorm<Eigen::Infinity>(), 1e-6 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()));
}

TEST(ProximalPoint, ProgressWindowStopsSlowRoutesAndIsInertOtherwise) {
  const LcpProblem p = fc2d_to_lcp(read_fc2d_dat(kData + "fc2d_granularflowonwall_02020_00213.dat").problem);
  SolverOptions o;
  const SolveResult a = solve_proximal_point(p, Eigen::VectorXd(), o);
  // A window longer than max_outer never fires: the same route, bit for bit.
  ProximalPointDef inert;
  inert.progress_window = inert.max_outer + 1;
  const SolveResult b = solve_proximal_point(p, Eigen::VectorXd(), o, inert);
  EXPECT_EQ(a.lambda, b.lambda);
  EXPECT_EQ(a.sweeps, b.sweeps);
  // A fall no pass achieves stops the route after its first outer iteration, at its best iterate.
  ProximalPointDef strict;
  strict.progress_window = 1;
  strict.progress_factor = 1e-30;
  const SolveResult c = solve_proximal_point(p, Eigen::VectorXd(), o, strict);
  EXPECT_EQ(c.status, SolveStatus::SweepLimit);
  EXPECT_NE(c.message.find("progress_factor"), std::string::npos) << c.message;
  EXPECT_LT(c.sweeps, a.sweeps);
  EXPECT_EQ(c.residual, natural_residual(p, c.lambda));
  // release_floor runs the same outer iterations first and at most continues after them: its
  // best residual is no worse.
  strict.release_floor = true;
  const SolveResult d = solve_proximal_point(p, Eigen::VectorXd(), o, strict);
  EXPECT_EQ(d.status, SolveStatus::SweepLimit);
  EXPECT_EQ(d.residual, natural_residual(p, d.lambda));
  EXPECT_LE(d.residual, c.residual);
  // With window_stops false the window never stops the route (it releases the floor instead):
  // the route ends at the target or max_outer, never with the window's message.
  strict.window_stops = false;
  strict.max_outer = 4;
  const SolveResult e = solve_proximal_point(p, Eigen::VectorXd(), o, strict);
  EXPECT_NE(e.message.find("outer iteration limit"), std::string::npos) << e.message;
  EXPECT_EQ(e.residual, natural_residual(p, e.lambda));
  EXPECT_LE(e.residual, c.residual);
}

TEST(ProximalPoint, RefusesInvalidSettingsAndGuesses) {
  TestRng rng(3);
  const LcpProblem p = without_jacobian(random_contact(6, 10, true, rng));
  SolverOptions o;
  ProximalPointDef bad;
  bad.initial_shift = -1;
  EXPECT_THROW(solve_proximal_point(p, Eigen::VectorXd(), o, bad), InvalidArgument);
  bad = {};
  bad.shrink = 1;
  EXPECT_THROW(solve_proximal_point(p, Eigen::VectorXd(), o, bad), InvalidArgument);
  bad = {};
  bad.min_shift = 1.0;
  EXPECT_THROW(solve_proximal_point(p, Eigen::VectorXd(), o, bad), InvalidArgument);
  bad = {};
  bad.inner_forcing = 1.0;
  EXPECT_THROW(solve_proximal_point(p, Eigen::VectorXd(), o, bad), InvalidArgument);
  bad = {};
  bad.floor_decay = 0.5;
  EXPECT_THROW(solve_proximal_point(p, Eigen::VectorXd(), o, bad), InvalidArgument);
  bad = {};
  bad.progress_factor = 0;
  EXPECT_THROW(solve_proximal_point(p, Eigen::VectorXd(), o, bad), InvalidArgument);
  Eigen::VectorXd nan_guess = Eigen::VectorXd::Zero(p.rows());
  nan_guess[0] = std::numeric_limits<double>::quiet_NaN();
  const SolveResult r = solve_proximal_point(p, nan_guess, o);
  EXPECT_EQ(r.status, SolveStatus::InvalidInput);
  EXPECT_TRUE(r.lambda.allFinite());
}

}  // namespace
}  // namespace dc
