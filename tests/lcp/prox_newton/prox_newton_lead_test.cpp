// prox-newton's lead stage (ProxNewtonDef::lead_sweeps): its stop rule (LeadRate), the same
// answer with and without it, and the caller's checkpoints numbered through it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/lead/lead_rate.hpp"

namespace dc {
namespace {

using solvers::prox::lead_window_chunks;
using solvers::prox::LeadRate;

SolverOptions tight(const LcpProblem& p) {
  SolverOptions o;
  o.max_sweeps = 300;
  o.tolerance = 1e-9 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
  return o;
}

double velocity_gap(const LcpProblem& p, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (lcp_velocity(p, a) - lcp_velocity(p, b)).cwiseAbs().maxCoeff();
}

TEST(ProxNewtonLead, RateRuleGoesOnOnlyWhileItReachesTheTargetWithinTheCap) {
  // lead_window = 0. 10-fold per chunk from 1 N: 1e-6 N five chunks after the first, 300 sweeps.
  const auto rate = [] { return LeadRate(1.0, 0, 2.0); };
  EXPECT_TRUE(rate().go_on(0.1, 1e-6, 50, 50, 2000));
  EXPECT_FALSE(rate().go_on(0.1, 1e-6, 50, 50, 250));
  // 0.9 per chunk: 130 more chunks.
  EXPECT_FALSE(rate().go_on(0.9, 1e-6, 50, 50, 2000));
  // No fall, a non-finite residual, or the target already met: stop.
  EXPECT_FALSE(rate().go_on(1.0, 1e-6, 50, 50, 2000));
  EXPECT_FALSE(rate().go_on(NAN, 1e-6, 50, 50, 2000));
  EXPECT_FALSE(rate().go_on(1e-7, 1e-6, 50, 50, 2000));
  // After the first chunk the rate is the one since its end: a fast first chunk and a slow
  // second one stop; two fast ones go on.
  LeadRate slow = rate();
  ASSERT_TRUE(slow.go_on(0.01, 1e-6, 50, 50, 2000));
  EXPECT_FALSE(slow.go_on(0.009, 1e-6, 100, 50, 2000));
  LeadRate fast = rate();
  ASSERT_TRUE(fast.go_on(0.01, 1e-6, 50, 50, 2000));
  EXPECT_TRUE(fast.go_on(0.001, 1e-6, 100, 50, 2000));
  // A chunk without a new best stops.
  EXPECT_FALSE(fast.go_on(0.001, 1e-6, 150, 50, 2000));
}

/// Feeds the best-so-far of `residuals` (one per chunk of 50) to a window rule; the chunks run
/// until it stops (or the sequence ends).
int chunks_run(LeadRate rate, const std::vector<double>& residuals, double target, int cap) {
  double best = INFINITY;
  for (std::size_t k = 0; k < residuals.size(); ++k) {
    best = std::min(best, residuals[k]);
    if (!rate.go_on(best, target, static_cast<int>(50 * (k + 1)), 50, cap)) return static_cast<int>(k + 1);
  }
  return static_cast<int>(residuals.size());
}

/// A non-monotone converging nncg: each block of 8 chunks starts with a new best 2.5-fold below
/// the last one, then climbs above it for 7 chunks.
std::vector<double> sawtooth(double start, int blocks) {
  std::vector<double> r;
  double low = start;
  for (int b = 0; b < blocks; ++b) {
    low /= 2.5;
    r.push_back(low);
    for (int k = 1; k < 8; ++k) r.push_back(low * (1 + 0.5 * k));
  }
  return r;
}

TEST(ProxNewtonLead, WindowRuleFollowsAConvergingNonMonotoneNncgToTheTarget) {
  // 2.5-fold per 8 chunks with 7 chunks between new bests: the window rule (8 chunks, 2-fold)
  // goes on to the chunk that reaches the target; the rate rule stops at the first chunk
  // without a new best.
  const std::vector<double> r = sawtooth(1.0, 20);
  const double target = 1.0 / std::pow(2.5, 12) * 1.01;  // the 12th block's new best
  EXPECT_EQ(chunks_run(LeadRate(1.0, 8, 2.0), r, target, 100000), 11 * 8 + 1);
  EXPECT_EQ(chunks_run(LeadRate(1.0, 0, 2.0), r, target, 100000), 2);
  // The cap stops it first.
  EXPECT_EQ(chunks_run(LeadRate(1.0, 8, 2.0), r, target, 50 * 30), 30);
  // 1.5-fold per 8 chunks, all of it in the first chunk, is too slow for 2-fold per 8 chunks:
  // pro rata from the start, chunk 5 asks for 2^(5/8) > 1.5.
  std::vector<double> slow;
  double low = 1.0;
  for (int b = 0; b < 10; ++b) {
    low /= 1.5;
    slow.push_back(low);
    for (int k = 1; k < 8; ++k) slow.push_back(low * 1.2);
  }
  EXPECT_EQ(chunks_run(LeadRate(1.0, 8, 2.0), slow, 1e-12, 100000), 5);
}

TEST(ProxNewtonLead, DefaultWindowAboveTheBodiesFollowsAnNncgFallingOneAndAHalfFoldPerWindow) {
  // nncg still converging 1.5-fold per window (as on the 250-body impact steps where it reaches
  // the target for less than the Newton part costs): the default window rule above
  // lead_window_bodies goes on to the chunk at the target within the default cap, the 2-fold
  // rule of smaller problems hands over at the first chunk.
  const ProxNewtonDef def;
  const int window = def.lead_window;
  std::vector<double> r;
  for (int k = 1; k <= 20 * window; ++k) r.push_back(std::pow(1.5, -static_cast<double>(k) / window));
  const int at_target = 10 * window;  // 1.5^-10
  const double target = r[static_cast<std::size_t>(at_target - 1)] * (1 + 1e-9);
  // Within the default cap (the target 8,000 sweeps in, chunks of 50 at a 16-chunk window).
  EXPECT_EQ(chunks_run(LeadRate(1.0, window, def.lead_window_gain_above), r, target, def.lead_sweeps), at_target);
  EXPECT_EQ(chunks_run(LeadRate(1.0, window, def.lead_window_gain), r, target, def.lead_sweeps), 1);
}

TEST(ProxNewtonLead, TheGainAboveAppliesOnlyAboveLeadWindowBodies) {
  // 40 bodies: with lead_window_bodies just below, the solve with lead_window_gain_above = g
  // is the solve with lead_window_gain = g at lead_window_bodies = 40 (the window 16 either
  // way: lround(16·√(40/39)) = 16), bit for bit; on either side the other gain is not read.
  // The two gains make different lead stages on this problem.
  test::TestRng rng(3500);
  const LcpProblem p = test::random_contact(40, 80, true, rng);
  SolverOptions o;
  o.max_sweeps = 100000;
  o.tolerance = 1e-300;
  auto solve = [&](double bodies, double gain, double above) {
    ProxNewtonDef d;
    d.lead_sweeps = 20000;
    d.safeguard_sweeps = 0;
    d.degenerate_rows = 1e9;  // the window rule alone (no probe, no degenerate stall rule)
    d.lead_window_bodies = bodies;
    d.lead_window_gain = gain;
    d.lead_window_gain_above = above;
    ProxNewtonSolver s(d);
    const SolveResult r = s.solve(p, {}, o);
    return std::make_pair(r.lambda, s.last_stats().lead_sweeps);
  };
  const auto ref = solve(40, 1.05, 1.05);
  const auto small = solve(40, 1.05, 100.0), large = solve(39, 100.0, 1.05), other = solve(39, 1.05, 100.0);
  EXPECT_EQ(small.second, ref.second);
  EXPECT_TRUE(small.first == ref.first);
  EXPECT_EQ(large.second, ref.second);
  EXPECT_TRUE(large.first == ref.first);
  EXPECT_NE(other.second, ref.second);
  ProxNewtonDef bad;
  bad.lead_window_gain_above = 1.0;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
}

TEST(ProxNewtonLead, WindowRuleHandsAStagnatingNncgOverWithinTheBound) {
  // 10-fold in the first chunk, then 1 % per chunk: less than 2-fold over the first window of
  // 16 chunks after the first: it stops at chunk 17.
  std::vector<double> r;
  for (int k = 1; k <= 200; ++k) r.push_back(0.1 * std::pow(0.99, k));
  EXPECT_EQ(chunks_run(LeadRate(1.0, 16, 2.0), r, 1e-9, 100000), 17);
  // Exactly 2-fold per window of 4, flat in between: it goes on (≤), the window compares with
  // the best 4 chunks earlier, and the first window with the start; a hair less stops.
  std::vector<double> steps;
  for (int k = 1; k <= 12; ++k) steps.push_back(std::ldexp(1.0, -(1 + (k - 1) / 4)));
  EXPECT_EQ(chunks_run(LeadRate(1.0, 4, 2.0), steps, 1e-9, 100000), 12);
  std::vector<double> short_of = steps;
  for (int k = 8; k < 12; ++k) short_of[static_cast<std::size_t>(k)] *= 1 + 1e-9;  // chunks 9–12
  EXPECT_EQ(chunks_run(LeadRate(1.0, 4, 2.0), short_of, 1e-9, 100000), 9);
  // A first chunk no better than the guess stops; so do a non-finite best and the target.
  EXPECT_EQ(chunks_run(LeadRate(1.0, 16, 2.0), {2.0, 0.5}, 1e-9, 100000), 1);
  EXPECT_FALSE(LeadRate(1.0, 16, 2.0).go_on(NAN, 1e-9, 50, 50, 100000));
  EXPECT_FALSE(LeadRate(1.0, 16, 2.0).go_on(1e-10, 1e-9, 50, 50, 100000));
}

TEST(ProxNewtonLead, StallRuleEndsAPlateauTheWindowRuleWaitsOut) {
  // 10-fold in the first chunk, then the best sits exactly still: the window rule (16 chunks,
  // 2-fold) waits the window out, the stall rule (6 chunks) stops after 6 chunks without a new
  // best; a plateau of 5 chunks followed by a new best goes on, and the stall rule leaves a
  // sequence with a new best at every chunk to the window rule.
  std::vector<double> flat(40, 0.1);
  EXPECT_EQ(chunks_run(LeadRate(1.0, 16, 2.0), flat, 1e-9, 100000), 17);
  EXPECT_EQ(chunks_run(LeadRate(1.0, 16, 2.0, 6), flat, 1e-9, 100000), 7);
  EXPECT_EQ(chunks_run(LeadRate(1.0, 16, 2.0, 0), flat, 1e-9, 100000), 17);
  std::vector<double> step = flat;
  for (std::size_t k = 6; k < step.size(); ++k) step[k] = 0.01;  // chunks 2–6 flat, a new best at 7
  EXPECT_EQ(chunks_run(LeadRate(1.0, 16, 2.0, 6), step, 1e-9, 100000), 13);
  std::vector<double> falling;
  for (int k = 1; k <= 40; ++k) falling.push_back(0.1 * std::pow(0.99, k));
  EXPECT_EQ(chunks_run(LeadRate(1.0, 16, 2.0, 6), falling, 1e-9, 100000),
            chunks_run(LeadRate(1.0, 16, 2.0), falling, 1e-9, 100000));
}

TEST(ProxNewtonLead, AStageThatReachesTheTargetLeavesNoNewtonPart) {
  // A loose target nncg reaches: no pass, no finish, no factorisation, the stage's answer.
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 3400);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    SolverOptions o;
    o.max_sweeps = 10000;
    o.tolerance = 1e-4 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
    ProxNewtonDef d;
    d.degenerate_drift_jumps = 0;  // 1.33 rows per velocity unknown: degenerate; nncg's own sweeps
    d.probe_sweeps = 0;            // and no probe, which can reach the loose target first
    ProxNewtonSolver s(d);
    const SolveResult r = s.solve(p, {}, o);
    const ProxNewtonStats st = s.last_stats();
    // (The status stays below Converged: the loose tolerance is above the solution target.)
    ASSERT_EQ(r.message.rfind("finished by nncg lead stage", 0), 0u) << r.message;
    EXPECT_GT(st.lead_sweeps, 0) << r.message;
    EXPECT_EQ(st.newton + st.finish_newton + st.outer + st.factorizations, 0) << r.message;
    EXPECT_EQ(r.sweeps, st.lead_sweeps);
    EXPECT_LE(r.residual, o.tolerance);
  }
}

TEST(ProxNewtonLead, AStagnatingStageStopsBeforeTheCap) {
  // A target below round-off: nncg's best stops falling, and the stage hands over to the
  // Newton part well before its cap.
  test::TestRng rng(3500);
  const LcpProblem p = test::random_contact(40, 80, true, rng);
  SolverOptions o;
  o.max_sweeps = 100000;
  o.tolerance = 1e-300;
  ProxNewtonDef def;
  def.lead_sweeps = 100000;
  def.lead_window = 4;
  def.safeguard_sweeps = 0;
  ProxNewtonSolver s(def);
  const SolveResult r = s.solve(p, {}, o);
  EXPECT_LT(s.last_stats().lead_sweeps, 20000) << r.message;
  ProxNewtonDef bad;
  bad.lead_window_gain = 1.0;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
  bad = {};
  bad.lead_window = -1;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
}

TEST(ProxNewtonLead, SameVelocitiesWithAndWithoutTheLeadStage) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 3100);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    ProxNewtonDef without;
    without.lead_sweeps = 0;
    ProxNewtonSolver a, b(without);
    const SolveResult ra = a.solve(p, {}, tight(p)), rb = b.solve(p, {}, tight(p));
    ASSERT_EQ(ra.status, SolveStatus::Converged) << ra.message;
    ASSERT_EQ(rb.status, SolveStatus::Converged) << rb.message;
    EXPECT_GT(a.last_stats().lead_sweeps, 0) << ra.message;
    EXPECT_EQ(b.last_stats().lead_sweeps, 0);
    EXPECT_LE(velocity_gap(p, ra.lambda, rb.lambda), 1e-6) << "seed " << seed;
  }
}

// The bound on the fallback sweeps applies to the Newton part from the lead iterate only: the
// part from the guess keeps finish_route's, so the answer reaches the target either way.
TEST(ProxNewtonLead, BoundedFallbackInTheLeadPartKeepsTheAnswer) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 3300);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    ProxNewtonDef bounded, unbounded;
    bounded.lead_fallback_doublings = 0;
    unbounded.lead_fallback_doublings = -1;
    ProxNewtonSolver a(bounded), b(unbounded);
    const SolveResult ra = a.solve(p, {}, tight(p)), rb = b.solve(p, {}, tight(p));
    ASSERT_EQ(ra.status, SolveStatus::Converged) << ra.message;
    ASSERT_EQ(rb.status, SolveStatus::Converged) << rb.message;
    EXPECT_LE(velocity_gap(p, ra.lambda, rb.lambda), 1e-6) << "seed " << seed;
  }
  ProxNewtonDef bad;
  bad.lead_fallback_doublings = 30;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
}

// The stop after a slow batch at the fallback cap applies to the Newton part from the lead
// iterate only: with the strictest rule there (every cap batch stops its solve) the answer
// reaches the target the part without it reaches.
TEST(ProxNewtonLead, FallbackCapStopInTheLeadPartKeepsTheAnswer) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 3300);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    ProxNewtonDef strict, off;
    strict.lead_fallback_cap_fall = 1e-12;
    strict.lead_fallback_doublings = 1;
    off.lead_fallback_cap_fall = 0;
    off.lead_fallback_doublings = 1;
    ProxNewtonSolver a(strict), b(off);
    const SolveResult ra = a.solve(p, {}, tight(p)), rb = b.solve(p, {}, tight(p));
    ASSERT_EQ(ra.status, SolveStatus::Converged) << ra.message;
    ASSERT_EQ(rb.status, SolveStatus::Converged) << rb.message;
    EXPECT_LE(velocity_gap(p, ra.lambda, rb.lambda), 1e-6) << "seed " << seed;
  }
  for (const double bad_fall : {-0.1, 1.5}) {
    ProxNewtonDef bad;
    bad.lead_fallback_cap_fall = bad_fall;
    EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument) << bad_fall;
  }
  NewtonSparseDef bad_ns;
  bad_ns.fallback_cap_fall = 2;
  EXPECT_THROW(NewtonSparseSolver{bad_ns}, InvalidArgument);
}

TEST(ProxNewtonLead, ASmallGainLeavesTheNewtonPartAsWithoutTheStage) {
  // One chunk short of the target and a gain below lead_gain: the Newton part runs from the
  // guess, bit for bit as without the stage, and its answer beats the stage's iterate.
  test::TestRng rng(3200);
  const LcpProblem p = test::random_contact(40, 80, true, rng);
  ProxNewtonDef with, without;
  with.lead_sweeps = 50;
  with.lead_gain = 1e300;
  without.lead_sweeps = 0;
  ProxNewtonSolver a(with), b(without);
  const SolveResult ra = a.solve(p, {}, tight(p)), rb = b.solve(p, {}, tight(p));
  ASSERT_EQ(ra.status, SolveStatus::Converged) << ra.message;
  ASSERT_EQ(a.last_stats().lead_sweeps, 50) << ra.message;
  ASSERT_GT(a.last_stats().newton + a.last_stats().finish_newton, 0) << ra.message;
  EXPECT_EQ(ra.lambda, rb.lambda);
  EXPECT_EQ(a.last_stats().newton, b.last_stats().newton);
  EXPECT_EQ(a.last_stats().factorizations, b.last_stats().factorizations);
}

TEST(ProxNewtonLead, CheckpointsCountTheLeadSweepsThenTheNewtonIterations) {
  // One chunk of lead sweeps does not reach the target: the Newton part finishes.
  test::TestRng rng(3200);
  const LcpProblem p = test::random_contact(40, 80, true, rng);
  SolverOptions o = tight(p);
  for (int k = 1; k <= 3000; ++k) o.checkpoints.push_back(k);
  std::vector<int> seen;
  Eigen::VectorXd last;
  o.on_checkpoint = [&](int k, const Eigen::VectorXd& lambda) {
    seen.push_back(k);
    last = lambda;
  };
  ProxNewtonDef def;
  def.lead_sweeps = 50;
  ProxNewtonSolver s(def);
  const SolveResult r = s.solve(p, {}, o);
  ASSERT_EQ(r.status, SolveStatus::Converged) << r.message;
  const ProxNewtonStats st = s.last_stats();
  ASSERT_EQ(st.lead_sweeps, 50) << r.message;
  ASSERT_GT(st.newton + st.finish_newton, 0) << r.message;
  EXPECT_EQ(r.sweeps, st.lead_sweeps + st.newton + st.finish_newton);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_LT(seen[i - 1], seen[i]);
  ASSERT_FALSE(seen.empty());
  EXPECT_GT(seen.back(), st.lead_sweeps);
  EXPECT_EQ(last, r.lambda);
}

TEST(ProxNewtonLead, WindowGrowsAsTheSquareRootOfTheBodiesAboveTheReference) {
  EXPECT_EQ(lead_window_chunks(16, 64, 60), 16);
  EXPECT_EQ(lead_window_chunks(16, 64, 64), 16);
  EXPECT_EQ(lead_window_chunks(16, 64, 256), 32);
  EXPECT_EQ(lead_window_chunks(16, 64, 1024), 64);
  EXPECT_EQ(lead_window_chunks(16, 0, 1024), 16);  // no reference: never scaled
  EXPECT_EQ(lead_window_chunks(0, 64, 1024), 0);   // the rate rule stays the rate rule
  ProxNewtonDef bad;
  bad.lead_window_bodies = -1;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
}

// The solver hands its body count (J's columns / 3) to the window: with a reference below it
// the window is longer, so the stage never stops sooner, and on some problem later.
TEST(ProxNewtonLead, TheSolverScalesTheWindowByItsBodies) {
  int later = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 3190);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    ProxNewtonDef fixed, scaled;
    fixed.lead_window = scaled.lead_window = 1;
    // A 1e4-fold fall asked per window: the first chunk's fall, between 1e4^(1/4) and 1e4 on
    // these problems, stops the one-chunk window and not the four-chunk one.
    fixed.lead_window_gain = scaled.lead_window_gain = 1e4;
    fixed.lead_window_bodies = 0;
    scaled.lead_window_bodies = 2.5;  // 40 bodies: a window of 4 chunks
    ProxNewtonSolver a(fixed), b(scaled);
    const SolveResult ra = a.solve(p, {}, tight(p)), rb = b.solve(p, {}, tight(p));
    ASSERT_EQ(ra.status, SolveStatus::Converged) << ra.message;
    ASSERT_EQ(rb.status, SolveStatus::Converged) << rb.message;
    EXPECT_LE(a.last_stats().lead_sweeps, b.last_stats().lead_sweeps) << "seed " << seed;
    if (a.last_stats().lead_sweeps < b.last_stats().lead_sweeps) ++later;
    EXPECT_LE(velocity_gap(p, ra.lambda, rb.lambda), 1e-6) << "seed " << seed;
  }
  EXPECT_GT(later, 0);
}

/// A Newton part from the lead stage's iterate that the passes leave to the proximal finish:
/// one chunk of lead sweeps, any gain, one single-iteration pass.
ProxNewtonDef first_part_to_the_finish() {
  ProxNewtonDef d;
  d.lead_sweeps = 50;
  d.lead_gain = 1;
  d.max_outer = 1;
  d.body_inner_iterations = 1;
  d.finish_iterations = 0;
  return d;
}

// lead_initial_shift and lead_newton_stalls change the proximal finish of the Newton part from
// the lead iterate (its work differs) and keep the answer: the part from the guess keeps
// finish_route's settings.
TEST(ProxNewtonLead, LeadPartShiftAndStallsChangeTheWorkNotTheAnswer) {
  for (const bool stalls : {false, true}) {
    int changed = 0, finished = 0;
    for (uint64_t seed = 1; seed <= 12; ++seed) {
      test::TestRng rng(seed + 3190);
      const LcpProblem p = test::random_contact(40, 80, true, rng);
      ProxNewtonDef plain = first_part_to_the_finish(), set = first_part_to_the_finish();
      plain.lead_initial_shift = 0;
      plain.lead_newton_stalls = 0;
      set.lead_initial_shift = stalls ? 0 : 1e-2;
      set.lead_newton_stalls = stalls ? 1 : 0;
      ProxNewtonSolver a(plain), b(set);
      const SolveResult ra = a.solve(p, {}, tight(p)), rb = b.solve(p, {}, tight(p));
      ASSERT_EQ(ra.status, SolveStatus::Converged) << ra.message;
      ASSERT_EQ(rb.status, SolveStatus::Converged) << rb.message;
      if (a.last_stats().proximal_finish_newton == 0) continue;  // the lead or the pass finished
      ++finished;
      EXPECT_LE(velocity_gap(p, ra.lambda, rb.lambda), 1e-6) << "seed " << seed;
      if (a.last_stats().finish_newton != b.last_stats().finish_newton ||
          a.last_stats().factorizations != b.last_stats().factorizations)
        ++changed;
    }
    ASSERT_GT(finished, 0);
    EXPECT_GT(changed, 0) << (stalls ? "lead_newton_stalls" : "lead_initial_shift");
  }
  for (const double bad_shift : {-1e-3, 1.0}) {
    ProxNewtonDef bad;
    bad.lead_initial_shift = bad_shift;
    EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument) << bad_shift;
  }
  ProxNewtonDef bad;
  bad.lead_newton_stalls = -1;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
}

}  // namespace
}  // namespace dc
