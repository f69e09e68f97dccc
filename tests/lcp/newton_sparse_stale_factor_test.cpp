// newton-sparse with a kept (stale) factor as GMRES's preconditioner (stale_factor_iterations):
// off by default, where a kept factor changes no result; on, the proximal-point route reaches
// the same target as with a factorisation per iteration, with fewer factorisations, and reports
// them (ProximalPointStats, ProxNewtonStats::factorizations).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "dc/lcp/proximal_point.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

SolverOptions options(int iterations = 200) {
  SolverOptions o;
  o.max_sweeps = iterations;
  o.record_theta = false;
  return o;
}

// The factor kept from a solve of another problem of the same pattern changes nothing with
// the default stale_factor_iterations = 0: bit-equal to a fresh solver's solve.
TEST(NewtonSparseStaleFactor, OffByDefaultAKeptFactorChangesNoResult) {
  ASSERT_EQ(NewtonSparseDef{}.stale_factor_iterations, 0);
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 2100);
    const LcpProblem p = test::random_contact(30, 40, true, rng, 0.3);
    LcpProblem q = p;
    for (int i = 0; i < q.rows(); ++i) q.b[i] *= 1.0 + 0.1 * rng.uniform(-1, 1);
    NewtonSparseSolver kept, fresh;
    (void)kept.solve(p, {}, options());
    const SolveResult a = kept.solve(q, {}, options());
    const SolveResult b = fresh.solve(q, {}, options());
    EXPECT_EQ(a.lambda, b.lambda) << seed;
    EXPECT_EQ(a.sweeps, b.sweeps) << seed;
    EXPECT_EQ(kept.last_stats().factorizations, fresh.last_stats().factorizations) << seed;
    EXPECT_EQ(kept.last_stats().stale_directions, 0) << seed;
  }
}

// The proximal-point route with stale-factor directions reaches the target a route with a
// factorisation per iteration reaches, and needs fewer factorisations in all; the counts it
// reports are those of its inner solves.
TEST(NewtonSparseStaleFactor, TheProximalRouteReachesTheSameTargetWithFewerFactorisations) {
  ProximalPointDef fresh_def;
  fresh_def.newton_sparse.krylov_forcing = 1e-2;
  ProximalPointDef stale_def = fresh_def;
  stale_def.newton_sparse.stale_factor_iterations = 30;
  long fresh_total = 0, stale_total = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed + 2200);
    const LcpProblem p = test::random_contact(30, 50, true, rng, 0.3);
    SolverOptions o = options();
    o.tolerance = 1e-8 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
    ProximalPointStats fs, ss;
    const SolveResult rf = solve_proximal_point(p, {}, o, fresh_def, &fs);
    const SolveResult rs = solve_proximal_point(p, {}, o, stale_def, &ss);
    EXPECT_LE(natural_residual(p, rf.lambda), o.tolerance) << seed << ": " << rf.message;
    EXPECT_LE(natural_residual(p, rs.lambda), o.tolerance) << seed << ": " << rs.message;
    EXPECT_GE(fs.factorizations, rf.sweeps > 0 ? 1 : 0) << seed;
    EXPECT_LE(ss.factorizations, rs.sweeps + 1) << seed;
    fresh_total += fs.factorizations;
    stale_total += ss.factorizations;
  }
  EXPECT_LT(stale_total, fresh_total);
}

// prox-newton counts the proximal finish's factorisations in its statistics: with one per
// finish iteration at least (stale factors off), at least as many as the finish's iterations;
// with the default stale factors, the same target.
TEST(NewtonSparseStaleFactor, ProxNewtonCountsTheProximalFinishsFactorisations) {
  test::TestRng rng(2300);
  const LcpProblem p = test::random_contact(30, 50, true, rng, 0.3);
  ProxNewtonDef def;
  def.lead_sweeps = 0;  // the Newton passes and the finish from the guess
  def.max_outer = 1;
  def.body_inner_iterations = 1;
  def.finish_iterations = 0;
  def.pivot_rows = 0;
  def.safeguard_sweeps = 0;
  ASSERT_GT(def.finish_route.newton_sparse.stale_factor_iterations, 0);
  ProxNewtonDef fresh_def = def;
  fresh_def.finish_route.newton_sparse.stale_factor_iterations = 0;
  SolverOptions o = options(2000);
  o.tolerance = 1e-8 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
  ProxNewtonSolver stale(def), fresh(fresh_def);
  const SolveResult rs = stale.solve(p, {}, o);
  const SolveResult rf = fresh.solve(p, {}, o);
  EXPECT_LE(natural_residual(p, rs.lambda), o.tolerance) << rs.message;
  EXPECT_LE(natural_residual(p, rf.lambda), o.tolerance) << rf.message;
  const ProxNewtonStats sf = fresh.last_stats();
  ASSERT_GT(sf.proximal_finish_newton, 0) << rf.message;
  EXPECT_GE(sf.factorizations, sf.proximal_finish_newton) << rf.message;
}

}  // namespace
}  // namespace dc
