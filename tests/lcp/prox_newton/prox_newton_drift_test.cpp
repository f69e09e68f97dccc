// prox-newton's drift jumps on degenerate problems (ProxNewtonDef::degenerate_drift_jumps,
// lead/drift_jump.hpp): the steps along a drift to the first row's bound. The jumps in the lead
// stage are tested on engine box-pile steps (tests/engine/solvers/prox_newton_drift_pile_test.cpp):
// on a drift this regular (duplicated contacts) nncg's momentum does not restart and reaches
// the bound itself within a chunk or two.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dc/lcp/prox_newton.hpp"
#include "solvers/prox_newton/lead/drift_jump.hpp"

namespace dc {
namespace {

/// Two contacts with friction μ = 0.5 on one body against the world (rows n0, t0, n1, t1).
LcpProblem drift_two_contacts() {
  LcpProblem p;
  const int n = 4;
  p.b = Eigen::VectorXd::Zero(n);
  p.lo = Eigen::VectorXd::Zero(n);
  p.hi = Eigen::VectorXd::Constant(n, INFINITY);
  p.mu = Eigen::VectorXd::Zero(n);
  p.normal_row.assign(n, -1);
  for (int c = 0; c < 2; ++c) {
    const ContactConstraint& k = p.constraints[p.constraints.add(-1, 0, 0.5)];
    p.normal_row[static_cast<size_t>(k.tangent_row)] = k.normal_row;
    p.mu[k.tangent_row] = 0.5;
    p.lo[k.tangent_row] = -INFINITY;
  }
  return p;
}

TEST(ProxNewtonDrift, StepsToTheFirstBoundCountNormalAndFrictionRows) {
  const LcpProblem p = drift_two_contacts();
  Eigen::VectorXd lambda(4), d(4);
  // Normal row 0 reaches 0 after 4 steps; friction row 1 (gap μλ_n − λ_t = 0.5 closing at
  // μ d_n − d_t = −0.25 per step) its upper bound after 2; friction row 3 rides its bound
  // (λ_t = μ λ_n, d_t = μ d_n up to round-off) and never counts.
  lambda << 2.0, 0.5, 3.0, 1.5;
  d << -0.5, 0.0, 0.1, 0.05 + 1e-15;
  EXPECT_DOUBLE_EQ(solvers::prox::drift_steps_to_bound(p, lambda, d), 2.0);
  d << -0.5, 0.0, 0.1, 0.05;
  lambda[1] = -0.5;  // the lower gap λ_t + μ λ_n = 0.5 closes at d_t + μ d_n = −0.25: still 2
  d[1] = 0.0;
  EXPECT_DOUBLE_EQ(solvers::prox::drift_steps_to_bound(p, lambda, d), 2.0);
  lambda[1] = 0.0;  // both friction gaps 1.0 closing at 0.25: the normal row first, after 4
  EXPECT_DOUBLE_EQ(solvers::prox::drift_steps_to_bound(p, lambda, d), 4.0);
  // Only the riding row moves, trailing its bound by less than a step's movement (as the sweep
  // leaves it) with a round-off slope towards it: no bound ahead.
  lambda[3] = 1.5 - 1e-3;
  d << 0.0, 0.0, 0.1, 0.05 + 1e-12;
  EXPECT_EQ(solvers::prox::drift_steps_to_bound(p, lambda, d), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace dc
