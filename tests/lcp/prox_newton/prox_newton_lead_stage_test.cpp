// prox-newton's lead stage as one nncg run (lead_stage.hpp) judged through nncg's per-chunk hook
// (SweepWatch): the hook sees the run's own iterates and ends it where asked; the stage is plain
// nncg to the sweep it stops at, and lands where 50-sweep restarts of nncg land; checkpoint_stats
// counts the work up to each checkpoint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/lead/lead_stage.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc {
namespace {

SolverOptions sweeps_only(int sweeps) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = 0.0;
  o.record_theta = false;
  return o;
}

TEST(NncgWatch, LooksEveryChunkAtTheRunsOwnIterateAndStopsWhereAsked) {
  test::TestRng rng(3600);
  const LcpProblem p = test::random_contact(40, 80, true, rng);
  ASSERT_TRUE(p.has_jacobian());
  const auto plain = solvers::make_nncg();
  std::vector<int> looks;
  std::vector<Eigen::VectorXd> seen;
  solvers::SweepWatch w;
  w.every = 7;
  w.stop = [&](int k, const Eigen::VectorXd& x) {
    looks.push_back(k);
    seen.push_back(x);
    return looks.size() == 3;
  };
  const SolveResult r = solvers::nncg_solve(p, {}, sweeps_only(1000), &w);
  ASSERT_EQ(looks, (std::vector<int>{7, 14, 21}));
  EXPECT_EQ(r.sweeps, 21);
  // Every look is the iterate plain nncg returns after as many sweeps (one run, momentum kept).
  for (std::size_t i = 0; i < looks.size(); ++i)
    EXPECT_EQ(seen[i], plain->solve(p, {}, sweeps_only(looks[i])).lambda) << looks[i];
  EXPECT_EQ(r.lambda, seen.back());
  // A hook that never stops leaves the run as without it.
  w.stop = [](int, const Eigen::VectorXd&) { return false; };
  EXPECT_EQ(solvers::nncg_solve(p, {}, sweeps_only(100), &w).lambda, plain->solve(p, {}, sweeps_only(100)).lambda);
}

TEST(ProxNewtonLeadStage, IsPlainNncgToTheSweepItStopsAt) {
  // A target nncg reaches: the stage's answer is nncg's iterate after the stage's sweeps.
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 3400);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    SolverOptions o;
    o.max_sweeps = 10000;
    o.tolerance = 1e-6 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
    ProxNewtonDef d;
    d.probe_sweeps = 0;  // 1.33 rows per velocity unknown: degenerate, where the probe would end the stage
    d.degenerate_drift_jumps = 0;  // plain nncg: no drift jumps either
    ProxNewtonSolver s(d);
    const SolveResult r = s.solve(p, {}, o);
    ASSERT_EQ(r.message.rfind("finished by nncg lead stage", 0), 0u) << r.message;
    const int sweeps = s.last_stats().lead_sweeps;
    EXPECT_EQ(sweeps % solvers::prox::kLeadChunk, 0) << sweeps;
    EXPECT_EQ(r.lambda, solvers::make_nncg()->solve(p, {}, sweeps_only(sweeps)).lambda) << "seed " << seed;
  }
}

TEST(ProxNewtonLeadStage, LandsWhereRestartedChunksOfNncgLand) {
  // 50-sweep runs of nncg, each restarted from the last one's iterate, to the same target: both
  // reach it, and their velocities agree to the target's order.
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 3400);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    const double target = 1e-7 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
    Eigen::VectorXd chunked = Eigen::VectorXd::Zero(p.rows());
    const auto nncg = solvers::make_nncg();
    int chunked_sweeps = 0;
    while (natural_residual(p, chunked) > target && chunked_sweeps < 20000) {
      chunked = nncg->solve(p, chunked, sweeps_only(solvers::prox::kLeadChunk)).lambda;
      chunked_sweeps += solvers::prox::kLeadChunk;
    }
    ASSERT_LE(natural_residual(p, chunked), target) << "seed " << seed;
    Eigen::VectorXd best;
    double best_res = INFINITY;
    solvers::prox::LeadStageDef d;
    d.cap = 20000;
    d.window = 16;
    d.start = natural_residual(p, Eigen::VectorXd::Zero(p.rows()));
    d.target = target;
    const int sweeps = solvers::prox::run_lead_stage(p, Eigen::VectorXd::Zero(p.rows()), d, {},
                                                     [&](const Eigen::VectorXd& x) {
                                                       const double res = natural_residual(p, x);
                                                       if (res < best_res) {
                                                         best_res = res;
                                                         best = x;
                                                       }
                                                       return best_res;
                                                     });
    ASSERT_LE(best_res, target) << "seed " << seed << ", " << sweeps << " sweeps";
    const double gap = (lcp_velocity(p, best) - lcp_velocity(p, chunked)).cwiseAbs().maxCoeff();
    const double scale = std::max(1.0, p.b.cwiseAbs().maxCoeff());
    EXPECT_LE(gap, 1e-5 * scale) << "seed " << seed;
  }
}

TEST(ProxNewtonLeadStage, CheckpointStatsCountTheWorkUpToEachCheckpoint) {
  // A target below what the lead stage reaches: the Newton part finishes. At every checkpoint k
  // the work so far counts k iterations (lead sweeps, then Newton iterations) and never more
  // factorisations than the whole solve, rising with k.
  test::TestRng rng(3200);
  const LcpProblem p = test::random_contact(40, 80, true, rng);
  SolverOptions o;
  o.max_sweeps = 3000;
  o.tolerance = 1e-9 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
  ProxNewtonDef def;
  def.lead_sweeps = 100;
  ProxNewtonSolver s(def);
  for (int k = 1; k <= 3000; ++k) o.checkpoints.push_back(k);
  std::vector<int> ks;
  std::vector<ProxNewtonStats> at;
  o.on_checkpoint = [&](int k, const Eigen::VectorXd&) {
    ks.push_back(k);
    at.push_back(s.checkpoint_stats());
  };
  const SolveResult r = s.solve(p, {}, o);
  ASSERT_EQ(r.status, SolveStatus::Converged) << r.message;
  const ProxNewtonStats whole = s.last_stats();
  ASSERT_GT(whole.factorizations, 0) << r.message;
  int last_fact = 0;
  for (std::size_t i = 0; i < ks.size(); ++i) {
    const ProxNewtonStats& a = at[i];
    if (ks[i] <= r.sweeps) {
      EXPECT_EQ(a.lead_sweeps + a.newton + a.finish_newton, ks[i]) << ks[i];
    }
    EXPECT_GE(a.factorizations, last_fact) << ks[i];
    EXPECT_LE(a.factorizations, whole.factorizations) << ks[i];
    last_fact = a.factorizations;
  }
  ASSERT_FALSE(at.empty());
  EXPECT_EQ(at.back().factorizations, whole.factorizations);
  EXPECT_EQ(at[static_cast<std::size_t>(whole.lead_sweeps - 1)].factorizations, 0);
}

}  // namespace
}  // namespace dc
