// newton-sparse's stop after a slow fallback batch at the cap (NewtonSparseDef::
// fallback_cap_fall): off by default; on, a solve whose fallback PGS sweeps reach their cap and
// do not lower ‖H‖∞ enough stops there as Failed, with fewer sweeps than without the rule; with
// no doublings (the cap is the first batch) it never fires.
#include <gtest/gtest.h>

#include <string>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

SolverOptions options() {
  SolverOptions o;
  o.max_sweeps = 60;
  o.record_theta = false;
  return o;
}

/// Settings whose Newton steps fail often: no backtracking (only full steps pass the line
/// search), no damping, one fallback sweep doubled at most `doublings` times.
NewtonSparseDef failing(int doublings, double cap_fall) {
  NewtonSparseDef d;
  d.max_backtracks = 0;
  d.max_damping = d.regularization;
  d.fallback_sweeps = 1;
  d.fallback_doublings = doublings;
  d.fallback_cap_fall = cap_fall;
  return d;
}

struct CapRun {
  SolveResult r;
  NewtonSparseStats st;
};

CapRun solve(const LcpProblem& p, const NewtonSparseDef& d) {
  NewtonSparseSolver s(d);
  CapRun out;
  out.r = s.solve(p, {}, options());
  out.st = s.last_stats();
  return out;
}

TEST(NewtonSparseFallbackCap, OffByDefault) { EXPECT_EQ(NewtonSparseDef{}.fallback_cap_fall, 0.0); }

// A cap batch that must lower ‖H‖∞ 10¹²-fold (never) stops the solve at the first cap batch:
// Failed, the rule named, fewer iterations (and no more sweeps) than the same settings without the rule,
// and the same iterate up to there (the rule changes no step before it fires).
TEST(NewtonSparseFallbackCap, ASlowCapBatchStopsTheSolve) {
  int fired = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 3100);
    const LcpProblem p = test::random_contact(20, 40, true, rng, 0.8);
    const CapRun off = solve(p, failing(2, 0.0));
    const CapRun on = solve(p, failing(2, 1e-12));
    if (off.st.pgs_sweeps < 1 + 2 + 4) continue;  // the doublings never reached the cap
    ++fired;
    EXPECT_EQ(on.r.status, SolveStatus::Failed) << seed;
    EXPECT_NE(on.r.message.find("fallback_cap_fall"), std::string::npos) << seed << ": " << on.r.message;
    EXPECT_LT(on.st.iterations, off.st.iterations) << seed;
    EXPECT_LE(on.st.pgs_sweeps, off.st.pgs_sweeps) << seed;
    // A cap batch is 4 sweeps; the solve stopped after its first one.
    EXPECT_GE(on.st.pgs_sweeps, 4) << seed;
    EXPECT_GE(natural_residual(p, on.r.lambda), natural_residual(p, off.r.lambda)) << seed;
  }
  EXPECT_GE(fired, 2);
}

// Without doublings every fallback batch is at the cap, but none is a repeat of a doubled one:
// the rule never fires and the solve is bit-equal to the one without it.
TEST(NewtonSparseFallbackCap, NoDoublingsNoStop) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed + 3100);
    const LcpProblem p = test::random_contact(20, 40, true, rng, 0.8);
    const CapRun off = solve(p, failing(0, 0.0));
    const CapRun on = solve(p, failing(0, 1e-12));
    ASSERT_GT(off.st.pgs_sweeps, 0) << seed;
    EXPECT_EQ(on.r.lambda, off.r.lambda) << seed;
    EXPECT_EQ(on.st.iterations, off.st.iterations) << seed;
    EXPECT_EQ(on.st.pgs_sweeps, off.st.pgs_sweeps) << seed;
  }
}

// A rule that asks no fall at all (fallback_cap_fall = 1: stop only when a cap batch raised
// ‖H‖∞) stops no later than one that asks a 10¹²-fold fall.
TEST(NewtonSparseFallbackCap, ALooserFallStopsNoEarlier) {
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 3100);
    const LcpProblem p = test::random_contact(20, 40, true, rng, 0.8);
    const CapRun strict = solve(p, failing(2, 1e-12));
    const CapRun loose = solve(p, failing(2, 1.0));
    EXPECT_GE(loose.st.iterations, strict.st.iterations) << seed;
  }
}

// The fallback sweeps with NNCG's momentum (NewtonSparseDef::fallback_momentum): off by default;
// a batch of one sweep has no move yet, so one-sweep batches are plain PGS bit for bit; longer
// batches move λ along the momentum (the solve differs) and the solve still reaches the solution.
TEST(NewtonSparseFallbackMomentum, OneSweepBatchesArePgsLongerOnesConverge) {
  EXPECT_FALSE(NewtonSparseDef{}.fallback_momentum);
  int differed = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 3100);
    const LcpProblem p = test::random_contact(20, 40, true, rng, 0.8);
    NewtonSparseDef plain = failing(0, 0.0), momentum = plain;
    momentum.fallback_momentum = true;
    const CapRun a = solve(p, plain), b = solve(p, momentum);
    ASSERT_GT(a.st.pgs_sweeps, 0) << seed;
    EXPECT_EQ(a.r.lambda, b.r.lambda) << seed;
    EXPECT_EQ(a.st.pgs_sweeps, b.st.pgs_sweeps) << seed;
    plain.fallback_sweeps = momentum.fallback_sweeps = 8;
    SolverOptions o = options();
    o.max_sweeps = 400;
    NewtonSparseSolver sp(plain), sm(momentum);
    const SolveResult rp = sp.solve(p, {}, o), rm = sm.solve(p, {}, o);
    ASSERT_GT(sm.last_stats().pgs_sweeps, 0) << seed;
    differed += rp.lambda != rm.lambda;
    EXPECT_EQ(rm.status, SolveStatus::Converged) << seed << ": " << rm.message;
  }
  EXPECT_GE(differed, 1);
}

}  // namespace
}  // namespace dc
