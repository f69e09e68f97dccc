// prox-newton on degenerate problems (ProxNewtonDef::degenerate_rows): from that many rows per
// velocity unknown on, the lead stage takes the stall rule with degenerate_stall_chunks and the
// proximal finish's fallback sweeps the momentum; below it, the settings elsewhere. The probe
// (prox_newton_probe_test.cpp) is off here.
#include <gtest/gtest.h>

#include <cmath>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

struct Outcome {
  SolveResult r;
  ProxNewtonStats st;
};

Outcome solve(const LcpProblem& p, const ProxNewtonDef& d) {
  SolverOptions o;
  o.max_sweeps = 500;
  o.tolerance = 1e-10 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
  ProxNewtonSolver s(d);
  Outcome out;
  out.r = s.solve(p, {}, o);
  out.st = s.last_stats();
  return out;
}

/// No problem counts as degenerate; `stall` chunks and the momentum set for every problem instead.
ProxNewtonDef everywhere(int stall, bool momentum) {
  ProxNewtonDef d;
  d.degenerate_rows = 1e9;
  d.probe_sweeps = 0;
  d.lead_stall_chunks = stall;
  d.finish_route.newton_sparse.fallback_momentum = momentum;
  return d;
}

void expect_same(const Outcome& a, const Outcome& b) {
  EXPECT_EQ(a.r.lambda, b.r.lambda);
  EXPECT_EQ(a.st.lead_sweeps, b.st.lead_sweeps);
  EXPECT_EQ(a.st.finish_newton, b.st.finish_newton);
  EXPECT_EQ(a.st.factorizations, b.st.factorizations);
}

TEST(ProxNewtonDegenerate, AboveTheRatioTheStallRuleAndTheMomentumApply) {
  // A resting pile with friction (rows per velocity unknown: ratio); the gate set just below
  // and just above that ratio.
  const LcpProblem p = test::deep_pile(12, 6, 0.9);
  const double ratio = static_cast<double>(p.rows()) / static_cast<double>(p.J.cols());
  ASSERT_GT(ratio, 1.0);
  ProxNewtonDef above;
  above.degenerate_rows = 0.99 * ratio;
  above.degenerate_stall_chunks = 4;
  above.probe_sweeps = 0;
  const Outcome gated = solve(p, above);
  expect_same(gated, solve(p, everywhere(4, true)));
  // The gate matters on this pile: without the two the solve differs.
  const Outcome off = solve(p, everywhere(0, false));
  EXPECT_NE(gated.r.lambda, off.r.lambda);
  // Below the ratio it is the solve without them.
  ProxNewtonDef below = above;
  below.degenerate_rows = 1.01 * ratio;
  expect_same(solve(p, below), off);
  // The default: the momentum and 6 stall chunks.
  ProxNewtonDef dflt;
  dflt.degenerate_rows = above.degenerate_rows;
  dflt.probe_sweeps = 0;
  expect_same(solve(p, dflt), solve(p, everywhere(6, true)));
}

TEST(ProxNewtonDegenerate, RefusesInvalidSettings) {
  ProxNewtonDef d;
  d.degenerate_rows = 0;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
  d = {};
  d.degenerate_stall_chunks = -1;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
  d = {};
  d.lead_stall_chunks = -1;
  EXPECT_THROW(ProxNewtonSolver{d}, InvalidArgument);
}

}  // namespace
}  // namespace dc
