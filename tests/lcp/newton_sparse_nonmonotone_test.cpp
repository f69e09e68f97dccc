// newton-sparse's non-monotone line search (NewtonSparseDef::nonmonotone_window): off by
// default; on, the same contact velocities as lemke and the dense newton, convergence from
// random starts, fewer failed line searches (and so fewer Levenberg–Marquardt dampings) where
// full steps switch modes, and the proximal-point route with it reaches its target.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/proximal_point.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/newton_sparse/merit_window.hpp"

namespace dc {
namespace {

SolverOptions options(int iterations = 200) {
  SolverOptions o;
  o.max_sweeps = iterations;
  o.record_theta = false;
  return o;
}

NewtonSparseDef windowed(int size) {
  NewtonSparseDef d;
  d.nonmonotone_window = size;
  return d;
}

TEST(MeritWindow, TheReferenceIsTheLargestOfTheLastMeritsAndTheCurrentOne) {
  solvers::MeritWindow w(3);
  EXPECT_EQ(w.reference(2.0), 2.0);  // empty: monotone
  for (const double m : {5.0, 1.0, 4.0, 3.0}) w.push(m);  // 5 has left the window
  EXPECT_EQ(w.reference(0.5), 4.0);
  EXPECT_EQ(w.reference(7.0), 7.0);
  solvers::MeritWindow off(0);
  off.push(9.0);
  EXPECT_EQ(off.reference(1.0), 1.0);
}

TEST(NewtonSparseNonmonotone, OffByDefault) { EXPECT_EQ(NewtonSparseDef{}.nonmonotone_window, 0); }

// λ is not unique on rank-deficient problems; w = A λ + b is, and it is what the engine uses.
TEST(NewtonSparseNonmonotone, SameContactVelocitiesAsLemkeAndNewton) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 4100);
    const LcpProblem rank_deficient = test::random_contact(10, 60, false, rng);  // 60 rows, rank ≤ 30
    const SolveResult a = make_solver("lemke")->solve(rank_deficient, {}, options(3000));
    const SolveResult b = NewtonSparseSolver(windowed(5)).solve(rank_deficient, {}, options());
    ASSERT_EQ(b.status, SolveStatus::Converged) << b.message;
    EXPECT_LE((lcp_velocity(rank_deficient, a.lambda) - lcp_velocity(rank_deficient, b.lambda)).cwiseAbs().maxCoeff(),
              1e-6)
        << seed;
    test::TestRng rng2(seed + 4200);
    const LcpProblem friction = test::random_contact(30, 25, true, rng2);
    const SolveResult c = make_solver("newton")->solve(friction, {}, options(3000));
    const SolveResult d = NewtonSparseSolver(windowed(5)).solve(friction, {}, options());
    ASSERT_EQ(c.status, SolveStatus::Converged) << c.message;
    ASSERT_EQ(d.status, SolveStatus::Converged) << d.message;
    EXPECT_LE((lcp_velocity(friction, c.lambda) - lcp_velocity(friction, d.lambda)).cwiseAbs().maxCoeff(), 1e-6)
        << seed;
  }
}

// From random nonnegative guesses far from the solution, on frictional problems with more rows
// than body dofs: converged (the watchdog brings a wandering iterate back to the best one), and
// the returned λ meets the target whatever the merit did on the way.
TEST(NewtonSparseNonmonotone, ConvergesFromRandomStarts) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 4300);
    const LcpProblem p = test::random_contact(20, 40, true, rng, 0.3);
    Eigen::VectorXd guess(p.rows());
    for (int i = 0; i < p.rows(); ++i) guess[i] = rng.uniform(0, 50);
    const SolveResult r = NewtonSparseSolver(windowed(5)).solve(p, guess, options());
    EXPECT_EQ(r.status, SolveStatus::Converged) << seed << ": " << r.message;
    EXPECT_LE(natural_residual(p, r.lambda), solution_target(p, options())) << seed;
  }
}

// A resting pile with friction from zero: full steps switch many modes at once, the monotone
// test rejects some of them and damps the free block; the window accepts them. Summed over a
// few piles: fewer failed line searches and dampings, the same target.
TEST(NewtonSparseNonmonotone, FewerFailedLineSearchesOnAFrictionalPile) {
  int monotone_failed = 0, window_failed = 0, monotone_damped = 0, window_damped = 0;
  for (const double mu : {0.2, 0.5, 0.8}) {
    const LcpProblem p = test::deep_pile(6, 8, mu);
    NewtonSparseSolver monotone, window(windowed(5));
    const SolveResult a = monotone.solve(p, {}, options());
    const SolveResult b = window.solve(p, {}, options());
    EXPECT_EQ(b.status, SolveStatus::Converged) << mu << ": " << b.message;
    if (a.status == SolveStatus::Converged) {
      EXPECT_LE((lcp_velocity(p, a.lambda) - lcp_velocity(p, b.lambda)).cwiseAbs().maxCoeff(), 1e-6) << mu;
    }
    monotone_failed += monotone.last_stats().failed_line_searches;
    window_failed += window.last_stats().failed_line_searches;
    monotone_damped += monotone.last_stats().dampings;
    window_damped += window.last_stats().dampings;
  }
  EXPECT_GT(monotone_failed, 0);
  EXPECT_LT(window_failed, monotone_failed);
  EXPECT_LE(window_damped, monotone_damped);
}

// The proximal-point route (prox-newton's finish) with the window in its inner solves reaches
// the target the monotone route reaches, on frictional piles from zero.
TEST(NewtonSparseNonmonotone, TheProximalRouteWithTheWindowReachesTheTarget) {
  for (const double mu : {0.3, 0.6}) {
    const LcpProblem p = test::deep_pile(6, 8, mu);
    ProximalPointDef monotone;
    monotone.newton_sparse.stale_factor_iterations = 30;
    ProximalPointDef window = monotone;
    window.newton_sparse.nonmonotone_window = 5;
    SolverOptions o = options(2000);
    o.tolerance = 1e-8 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
    const SolveResult a = solve_proximal_point(p, {}, o, monotone);
    const SolveResult b = solve_proximal_point(p, {}, o, window);
    EXPECT_LE(natural_residual(p, a.lambda), o.tolerance) << mu << ": " << a.message;
    EXPECT_LE(natural_residual(p, b.lambda), o.tolerance) << mu << ": " << b.message;
  }
}

}  // namespace
}  // namespace dc
