// prox-newton's Newton-part budget (ProxNewtonDef::newton_budget): the first Newton part stops
// after its factorisation budget without progress, and nncg goes on from the best iterate of the
// parts before it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

/// One checkpoint: the iterate and the work up to it.
struct Seen {
  Eigen::VectorXd lambda;
  ProxNewtonStats work;
};

/// The solve with a checkpoint at every iteration; `seen` gets them in order.
SolveResult traced(ProxNewtonSolver& s, const LcpProblem& p, const SolverOptions& base, std::vector<Seen>& seen) {
  SolverOptions o = base;
  o.checkpoints.clear();
  for (int k = 1; k <= 20000; ++k) o.checkpoints.push_back(k);
  o.on_checkpoint = [&](int, const Eigen::VectorXd& lambda) { seen.push_back({lambda, s.checkpoint_stats()}); };
  return s.solve(p, {}, o);
}

/// A pile nncg converges on slowly, with the first Newton part always run (lead_gain = 1).
ProxNewtonDef stalling(int budget) {
  ProxNewtonDef d;
  d.lead_sweeps = 400;
  d.lead_gain = 1;
  d.newton_budget = budget;
  d.newton_budget_lead_fall = 0;  // whatever the lead stage's fall
  d.safeguard_sweeps = 300;
  d.pivot_rows = 0;
  return d;
}

/// A pile whose first Newton part creeps towards a tight target (tens of factorisations without
/// the budget, against a few with it).
LcpProblem stalling_pile() { return test::deep_pile(12, 6, 0.9); }

SolverOptions tight(const LcpProblem& p) {
  SolverOptions o;
  o.max_sweeps = 500;  // Newton iterations of a part (the unbudgeted ones stall far longer)
  o.tolerance = 1e-10 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
  return o;
}

/// Index of the first checkpoint of the safeguard (seen.size() when none).
std::size_t first_safeguard(const std::vector<Seen>& seen) {
  std::size_t k = 0;
  while (k < seen.size() && seen[k].work.safeguard_sweeps == 0) ++k;
  return k;
}

TEST(ProxNewtonBudget, StopsAStallingFirstPartAndNncgGoesOnFromTheBestIterate) {
  const LcpProblem p = stalling_pile();
  const SolverOptions o = tight(p);
  ProxNewtonSolver unbudgeted(stalling(0)), budgeted(stalling(1));
  std::vector<Seen> all, cut;
  (void)traced(unbudgeted, p, o, all);
  (void)traced(budgeted, p, o, cut);
  const std::size_t s1 = first_safeguard(cut);
  ASSERT_LT(s1, cut.size());
  // The budget hands over to nncg after a few factorisations, where the Newton parts ran on.
  EXPECT_LT(10 * cut[s1].work.factorizations, unbudgeted.last_stats().factorizations);
  EXPECT_EQ(cut[s1].work.lead_sweeps, stalling(1).lead_sweeps);
  // nncg starts from the best iterate of the parts before it: the lead stage's looks (every
  // 50 sweeps) and every iterate after the stage.
  double best = INFINITY;
  Eigen::VectorXd from;
  for (std::size_t k = 0; k < s1; ++k) {
    const ProxNewtonStats& w = cut[k].work;
    const bool looked = w.newton + w.finish_newton + w.outer > 0 || w.lead_sweeps % 50 == 0;
    const double res = natural_residual(p, cut[k].lambda);
    if (looked && res < best) {
      best = res;
      from = cut[k].lambda;
    }
  }
  ASSERT_EQ(from.size(), p.rows());
  SolverOptions one;
  one.max_sweeps = 1;
  one.tolerance = 0.0;
  one.record_theta = false;
  const Eigen::VectorXd expected = make_solver("nncg")->solve(p, from, one).lambda;
  EXPECT_EQ(cut[s1].work.safeguard_sweeps, 1);
  EXPECT_TRUE(cut[s1].lambda == expected) << (cut[s1].lambda - expected).cwiseAbs().maxCoeff();
}

TEST(ProxNewtonBudget, StopsTheProximalFinishAfterAnOuterIteration) {
  // Here the passes make fewer factorisations than the budget and the proximal finish runs on
  // for tens of outer iterations without it: the budget stops it after its first.
  const LcpProblem p = test::deep_pile(16, 8, 0.9);
  const SolverOptions o = tight(p);
  ProxNewtonSolver unbudgeted(stalling(0)), budgeted(stalling(4));
  std::vector<Seen> all, cut;
  (void)traced(unbudgeted, p, o, all);
  (void)traced(budgeted, p, o, cut);
  const std::size_t k = first_safeguard(cut);
  ASSERT_LT(k, cut.size());
  EXPECT_GT(cut[k].work.proximal_finish_newton, 0);
  const std::size_t k0 = first_safeguard(all);
  const int unbudgeted_finish = (k0 < all.size() ? all[k0] : all.back()).work.proximal_finish_newton;
  EXPECT_LT(2 * cut[k].work.proximal_finish_newton, unbudgeted_finish);
}

TEST(ProxNewtonBudget, AnswerIsTheBestIterateOfEveryPart) {
  const LcpProblem p = stalling_pile();
  const SolverOptions o = tight(p);
  ProxNewtonSolver s(stalling(1));
  std::vector<Seen> seen;
  const SolveResult r = traced(s, p, o, seen);
  double best = INFINITY;
  for (const Seen& x : seen) best = std::min(best, natural_residual(p, x.lambda));
  // No checkpoint iterate of any part beats the answer by more than round-off of the residual.
  EXPECT_LE(r.residual, best * (1 + 1e-12)) << r.message;
}

TEST(ProxNewtonBudget, RerunsAreBitEqual) {
  const LcpProblem p = stalling_pile();
  const SolverOptions o = tight(p);
  ProxNewtonSolver a(stalling(2)), b(stalling(2));
  const SolveResult ra = a.solve(p, {}, o), rb = b.solve(p, {}, o), ra2 = a.solve(p, {}, o);
  EXPECT_TRUE(ra.lambda == rb.lambda);
  EXPECT_TRUE(ra.lambda == ra2.lambda);
  EXPECT_EQ(a.last_stats().factorizations, b.last_stats().factorizations);
  EXPECT_EQ(ra.message, rb.message);
}

TEST(ProxNewtonBudget, ABudgetNeverSpentChangesNothing) {
  const LcpProblem p = stalling_pile();
  const SolverOptions o = tight(p);
  // A budget never reached, or one the lead stage's fall does not open (its fall over a window
  // is finite): the solve of no budget, bit for bit.
  ProxNewtonDef gated = stalling(1);
  gated.newton_budget_lead_fall = 1e300;
  ProxNewtonSolver a(stalling(0)), b(stalling(1000000)), c(gated);
  const SolveResult ra = a.solve(p, {}, o), rb = b.solve(p, {}, o), rc = c.solve(p, {}, o);
  EXPECT_TRUE(ra.lambda == rb.lambda);
  EXPECT_EQ(ra.message, rb.message);
  EXPECT_EQ(a.last_stats().factorizations, b.last_stats().factorizations);
  EXPECT_TRUE(ra.lambda == rc.lambda);
  EXPECT_EQ(ra.message, rc.message);
}

TEST(ProxNewtonBudget, RefusesInvalidSettings) {
  const auto with = [](int budget, double gain, double fall = 1.5) {
    ProxNewtonDef d;
    d.newton_budget = budget;
    d.newton_budget_gain = gain;
    d.newton_budget_lead_fall = fall;
    return d;
  };
  EXPECT_THROW(ProxNewtonSolver(with(-1, 2.0)), InvalidArgument);
  EXPECT_THROW(ProxNewtonSolver(with(4, 0.5)), InvalidArgument);
  EXPECT_THROW(ProxNewtonSolver(with(4, NAN)), InvalidArgument);
  EXPECT_THROW(ProxNewtonSolver(with(4, INFINITY)), InvalidArgument);
  EXPECT_THROW(ProxNewtonSolver(with(4, 2.0, -1.0)), InvalidArgument);
  EXPECT_THROW(ProxNewtonSolver(with(4, 2.0, NAN)), InvalidArgument);
  EXPECT_NO_THROW(ProxNewtonSolver(with(0, 1.0, 0.0)));
}

}  // namespace
}  // namespace dc
