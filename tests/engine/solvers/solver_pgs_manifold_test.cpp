// The two-point manifold block of "pgs" (lcp/src/solvers/pgs_manifold_block.hpp): on a
// problem that is one manifold, one sweep is the exact solution of the 2 × 2 LCP in each of
// its four cases (= lemke); an ill-conditioned manifold runs row by row; on a settled box pile
// the block and the row-by-row order converge to the same solution.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

SolverOptions sweeps(int k, bool block, double tol = 0.0) {
  SolverOptions o;
  o.max_sweeps = k;
  o.tolerance = tol;
  o.block_manifolds = block;
  return o;
}

/// A box face resting on the floor (two_bodies = false: body 0 alone, a wall contact) or on
/// the top face of body 0 (body 1 on body 0), touching at the horizontal offsets x0, x1 from
/// the centres (the boxes are aligned, half-height 0.5 m, normal (0, 1) from the lower body to
/// the upper one): normal row [n, r×n] per point, r×n = x_k, tangent row t = (−1, 0),
/// r×t = ∓0.5 when μ > 0. Random masses; b = 0 (set by the caller).
LcpProblem face_manifold(double x0, double x1, bool two_bodies, double mu, test::TestRng& rng) {
  const int bodies = two_bodies ? 2 : 1;
  LcpProblem p;
  std::vector<Eigen::Triplet<double>> trip;
  const double xs[2] = {x0, x1};
  for (int k = 0; k < 2; ++k) {
    const ContactConstraint& c = p.constraints[p.constraints.add(two_bodies ? 0 : -1, two_bodies ? 1 : 0, mu, k + 1)];
    const int top = two_bodies ? 3 : 0;  // Δu offset of the upper body
    trip.emplace_back(c.normal_row, top + 1, 1.0);
    trip.emplace_back(c.normal_row, top + 2, xs[k]);
    if (two_bodies) {
      trip.emplace_back(c.normal_row, 1, -1.0);
      trip.emplace_back(c.normal_row, 2, -xs[k]);
    }
    if (c.has_friction()) {
      trip.emplace_back(c.tangent_row, top + 0, -1.0);
      trip.emplace_back(c.tangent_row, top + 2, -0.5);
      if (two_bodies) {
        trip.emplace_back(c.tangent_row, 0, 1.0);
        trip.emplace_back(c.tangent_row, 2, -0.5);
      }
    }
  }
  const int n = p.constraints.rows();
  p.b = Eigen::VectorXd::Zero(n);
  p.lo = Eigen::VectorXd::Zero(n);
  p.hi = Eigen::VectorXd::Constant(n, INFINITY);
  p.mu = Eigen::VectorXd::Zero(n);
  p.normal_row.assign(static_cast<size_t>(n), -1);
  for (const ContactConstraint& c : p.constraints)
    if (c.has_friction()) {
      p.normal_row[static_cast<size_t>(c.tangent_row)] = c.normal_row;
      p.mu[c.tangent_row] = c.mu;
      p.lo[c.tangent_row] = -INFINITY;
    }
  p.J.resize(n, 3 * bodies);
  p.J.setFromTriplets(trip.begin(), trip.end());
  p.J.makeCompressed();
  p.inv_mass.resize(3 * bodies);
  for (int k = 0; k < bodies; ++k) {
    const double m = rng.uniform(0.5, 2.0);
    p.inv_mass[3 * k] = p.inv_mass[3 * k + 1] = 1.0 / m;
    p.inv_mass[3 * k + 2] = 1.0 / (m / 6.0);  // unit square: I = m (1 + 1)/12
  }
  p.dt = 0.01;
  return p;
}

TEST(PgsManifoldBlock, OneSweepSolvesATwoPointLcpExactlyInEachCase) {
  test::TestRng rng(3);
  const auto pgs = make_solver("pgs"), lemke = make_solver("lemke");
  int row_by_row_inexact = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const bool two_bodies = trial % 2 == 1;
    const double x0 = rng.uniform(-0.5, -0.05), x1 = rng.uniform(0.05, 0.5);
    LcpProblem p = face_manifold(x0, x1, two_bodies, 0.0, rng);
    p.ensure_assembled_matrix();
    const Eigen::MatrixXd A(p.A);
    // Target solution of case (trial / 2) % 4: both points active, point 0 only, point 1
    // only, none; b = w* − A λ* with w*_i > 0 exactly where λ*_i = 0.
    const int which = (trial / 2) % 4;
    Eigen::VectorXd lam_star(2), w_star = Eigen::VectorXd::Zero(2);
    lam_star << rng.uniform(0.5, 3), rng.uniform(0.5, 3);
    for (int k = 0; k < 2; ++k)
      if ((which == 1 && k == 1) || (which == 2 && k == 0) || which == 3) {
        lam_star[k] = 0;
        w_star[k] = rng.uniform(0.01, 0.1);
      }
    p.b = w_star - A * lam_star;
    Eigen::VectorXd l0(2);
    l0 << rng.uniform(0, 3), rng.uniform(0, 3);
    const SolveResult exact = lemke->solve(p, Eigen::VectorXd(), SolverOptions());
    ASSERT_EQ(exact.status, SolveStatus::Converged) << exact.message;
    const double scale = std::max(1.0, max_abs(lam_star));
    ASSERT_LE(max_abs(exact.lambda - lam_star), 1e-9 * scale);
    const SolveResult block = pgs->solve(p, l0, sweeps(1, true));
    ASSERT_EQ(block.sweeps, 1);
    EXPECT_LE(max_abs(block.lambda - exact.lambda), 1e-12 * scale) << "trial " << trial << " case " << which;
    EXPECT_LE(block.residual, 1e-12 * scale);
    // Row by row, one sweep is not the solution unless the first row's update already is.
    const SolveResult rows = pgs->solve(p, l0, sweeps(1, false));
    if (max_abs(rows.lambda - exact.lambda) > 1e-6 * scale) ++row_by_row_inexact;
  }
  EXPECT_GE(row_by_row_inexact, 10);  // the block, not luck, solved it
}

TEST(PgsManifoldBlock, IllConditionedManifoldRunsRowByRow) {
  test::TestRng rng(5);
  // Two points 1e-7 m apart: the block's condition estimate max(A_00, A_11)²/det is far
  // above 1000, so both contacts take the row-by-row kernels: iterates bit-equal.
  for (const bool two_bodies : {false, true})
    for (const double mu : {0.0, 0.5}) {
      LcpProblem p = face_manifold(0.3, 0.3 + 1e-7, two_bodies, mu, rng);
      for (int i = 0; i < p.rows(); ++i) p.b[i] = p.is_friction_row(i) ? rng.uniform(-0.1, 0.1) : -0.1;
      const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(7, true));
      const SolveResult b = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(7, false));
      ASSERT_EQ(a.lambda.size(), b.lambda.size());
      for (int i = 0; i < p.rows(); ++i) EXPECT_EQ(a.lambda[i], b.lambda[i]) << "row " << i;
      EXPECT_EQ(a.theta, b.theta);
    }
}

TEST(PgsManifoldBlock, FrictionManifoldConvergesToTheRowByRowSolution) {
  test::TestRng rng(9);
  for (int trial = 0; trial < 6; ++trial) {
    LcpProblem p = face_manifold(rng.uniform(-0.5, -0.1), rng.uniform(0.1, 0.5), trial % 2 == 1, 0.4, rng);
    for (int i = 0; i < p.rows(); ++i) p.b[i] = p.is_friction_row(i) ? rng.uniform(-0.3, 0.3) : rng.uniform(-0.2, 0);
    const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(100000, true, 1e-13));
    const SolveResult b = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(100000, false, 1e-13));
    ASSERT_EQ(a.status, SolveStatus::Converged) << a.message;
    ASSERT_EQ(b.status, SolveStatus::Converged) << b.message;
    const double scale = std::max(1.0, max_abs(b.lambda));
    EXPECT_LE(a.residual, 1e-10 * scale);
    EXPECT_LE(max_abs(a.lambda - b.lambda), 1e-8 * scale) << "trial " << trial;
  }
}

/// Contacts whose predecessor in the constraint list is the other point of a manifold (same
/// bodies, another feature, rows right after it).
int manifold_pairs(const LcpProblem& p) {
  int pairs = 0;
  for (int c = 0; c + 1 < p.constraints.size(); ++c) {
    const ContactConstraint &k0 = p.constraints[c], &k1 = p.constraints[c + 1];
    if (k0.body_a == k1.body_a && k0.body_b == k1.body_b && k0.feature != k1.feature) ++pairs;
  }
  return pairs;
}

/// A resting box structure after `steps` steps: a stack of 8 boxes (pyramid = false) or a
/// pyramid of base 6 whose boxes stand 5 cm apart (each box rests on two: two manifolds, four
/// points, more contact rows than degrees of freedom), 1 × 1 m boxes on the floor.
LcpProblem boxes_problem(bool pyramid, double mu, int steps) {
  WorldDef d;
  d.bodies.count = 0;
  d.world.width = d.world.height = 40.0;
  d.world.walls = {false, false, true, false};
  d.contact.friction = mu;
  const int base = pyramid ? 6 : 1, rows = pyramid ? 6 : 8;
  for (int row = 0; row < rows; ++row)
    for (int k = 0; k < base - (pyramid ? row : 0); ++k) {
      BodyDef b;
      b.shape = BodyShape::Box;
      b.size = {1, 1};
      b.position = {20 + (k - 0.5 * (base - (pyramid ? row : 0) - 1)) * 1.05, 0.5 + row};
      d.body.push_back(b);
    }
  World w(d);
  const auto pgs = make_solver("pgs");
  SolverOptions o = sweeps(200, true);
  o.record_theta = false;
  for (int s = 0; s < steps; ++s) w.step(*pgs, o);
  w.collide();
  return w.assemble();
}

TEST(PgsManifoldBlock, BlockAndRowByRowConvergeToTheSameSolutionOnBoxStructures) {
  // The stacks have a unique frictionless solution and converge to 1e-11; with friction the
  // split of the tangent force between a face's two points is not unique (both have the same
  // r × t), nor is much of the pyramid's solution (four points per box), and there both
  // orders creep along the solution set (θ stalls near 1e-4 N while the natural residual is
  // ~1e-6 of the load): compare the impulse on the bodies, Jᵀλ, which is what moves them.
  struct Case {
    bool pyramid;
    double mu, residual;  // required natural residual relative to max |λ|
  };
  for (const Case k : {Case{false, 0.0, 1e-10}, Case{false, 0.5, 1e-10}, Case{true, 0.5, 2e-6}}) {
    const LcpProblem p = boxes_problem(k.pyramid, k.mu, 50);
    const std::string what = std::string(k.pyramid ? "pyramid" : "stack") + " mu " + std::to_string(k.mu);
    ASSERT_GE(manifold_pairs(p), k.pyramid ? 30 : 8) << what;
    const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(100000, true, 1e-11));
    const SolveResult b = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(100000, false, 1e-11));
    if (!k.pyramid) {
      EXPECT_EQ(a.status, SolveStatus::Converged) << what << ": " << a.message;
      EXPECT_EQ(b.status, SolveStatus::Converged) << what << ": " << b.message;
    }
    const double scale = std::max(1.0, max_abs(b.lambda));
    EXPECT_LE(a.residual, k.residual * scale) << what;
    EXPECT_LE(b.residual, k.residual * scale) << what;
    const Eigen::VectorXd ja = p.J.transpose() * a.lambda, jb = p.J.transpose() * b.lambda;
    const double tol_j = k.pyramid ? 1e-5 : 1e-9;
    EXPECT_LE(max_abs(ja - jb), tol_j * std::max(1.0, max_abs(jb))) << what << " max |Jᵀλ| " << max_abs(jb);
    if (k.mu == 0) { EXPECT_LE(max_abs(a.lambda - b.lambda), 1e-9 * scale) << what; }
  }
}

}  // namespace
}  // namespace dc
