// The two PGS forms (matrix-free "pgs" and "pgs-assembled") and PSOR: same iterates, the
// fixed-sweep / tolerance modes, θ recording and checkpoints.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

SolveResult run(const std::string& name, const LcpProblem& p, int sweeps, double tol = 0.0,
                const Eigen::VectorXd& l0 = Eigen::VectorXd(), double omega = 1.0) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = tol;
  o.omega = omega;
  return make_solver(name)->solve(p, l0, o);
}

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

class SolverPgsIterates : public ::testing::TestWithParam<bool> {};

TEST_P(SolverPgsIterates, MatrixFreeMatchesAssembledAfter1_10_100Sweeps) {
  const bool friction = GetParam();
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed);
    const LcpProblem p = test::random_contact(40, 70, friction, rng);
    ASSERT_TRUE(p.has_jacobian());
    for (int k : {1, 10, 100}) {
      const SolveResult mf = run("pgs", p, k), as = run("pgs-assembled", p, k);
      ASSERT_EQ(mf.status, SolveStatus::SweepLimit) << mf.message;
      ASSERT_EQ(as.status, SolveStatus::SweepLimit) << as.message;
      ASSERT_EQ(mf.sweeps, k);
      const double scale = std::max(1.0, max_abs(as.lambda));
      EXPECT_LE(max_abs(mf.lambda - as.lambda), 1e-10 * scale) << "seed " << seed << " sweeps " << k;
      ASSERT_EQ(mf.theta.size(), as.theta.size());
      for (size_t s = 0; s < mf.theta.size(); ++s) EXPECT_NEAR(mf.theta[s], as.theta[s], 1e-10 * scale);
    }
  }
}

TEST_P(SolverPgsIterates, MatrixFreeMatchesAssembledFromWarmStart) {
  test::TestRng rng(11);
  const LcpProblem p = test::random_contact(30, 50, GetParam(), rng);
  Eigen::VectorXd l0(p.rows());
  for (int i = 0; i < p.rows(); ++i) l0[i] = rng.uniform(-1, 3);
  const SolveResult mf = run("pgs", p, 20, 0.0, l0), as = run("pgs-assembled", p, 20, 0.0, l0);
  EXPECT_LE(max_abs(mf.lambda - as.lambda), 1e-10 * std::max(1.0, max_abs(as.lambda)));
}

INSTANTIATE_TEST_SUITE_P(SolverPgsFriction, SolverPgsIterates, ::testing::Values(false, true));

/// The rows `order` of p (indices into p's rows) as a new problem; friction rows keep their
/// coupling (their normal row must be in `order` too); A is rebuilt as J M⁻¹ Jᵀ Δt.
LcpProblem select_rows(const LcpProblem& p, const std::vector<int>& order) {
  const int n = static_cast<int>(order.size());
  std::vector<int> where(static_cast<size_t>(p.rows()), -1);
  for (int k = 0; k < n; ++k) where[static_cast<size_t>(order[static_cast<size_t>(k)])] = k;
  LcpProblem q;
  q.b.resize(n);
  q.lo.resize(n);
  q.hi.resize(n);
  q.mu.resize(n);
  q.normal_row.assign(static_cast<size_t>(n), -1);
  std::vector<Eigen::Triplet<double>> trip;
  for (int k = 0; k < n; ++k) {
    const int i = order[static_cast<size_t>(k)];
    for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it) trip.emplace_back(k, it.col(), it.value());
    q.b[k] = p.b[i];
    q.lo[k] = p.lo[i];
    q.hi[k] = p.hi[i];
    q.mu[k] = p.mu[i];
    const int nr = p.normal_row[static_cast<size_t>(i)];
    q.normal_row[static_cast<size_t>(k)] = nr < 0 ? -1 : where[static_cast<size_t>(nr)];
  }
  q.J.resize(n, p.J.cols());
  q.J.setFromTriplets(trip.begin(), trip.end());
  q.J.makeCompressed();
  q.inv_mass = p.inv_mass;
  q.dt = p.dt;
  const SparseRowMatrix Minv_Jt_dt = (q.inv_mass.asDiagonal() * SparseRowMatrix(q.J.transpose())) * q.dt;
  q.A = q.J * Minv_Jt_dt;
  q.A.makeCompressed();
  return q;
}

// The matrix-free solver sorts rows into kernels (contact blocks = normal + its tangent row
// right after it, frictionless normal rows, general rows) and runs them in row order. A
// problem that alternates all kinds must still give the iterates of pgs-assembled.
TEST(SolverPgs, MatrixFreeMatchesAssembledWithMixedRowKinds) {
  for (uint64_t seed = 21; seed <= 23; ++seed) {
    test::TestRng rng(seed);
    const LcpProblem base = test::random_contact(30, 48, true, rng);
    std::vector<int> order;
    for (int c = 0; c < 48; ++c) {
      const int rn = 2 * c, rt = rn + 1;
      switch (c % 6) {
        case 0: case 4: order.insert(order.end(), {rn, rt}); break;  // contact block
        case 1: order.insert(order.end(), {rt, rn}); break;          // tangent before its normal
        case 2: order.push_back(rn); break;                          // frictionless contact
        case 3: order.insert(order.end(), {rn, rt}); break;          // normal with finite hi, below
        case 5: order.push_back(rn); order.push_back(2 * ((c + 7) % 48) + 1); break;  // tangent far from its normal
      }
    }
    // Friction rows whose normal row was not selected are dropped.
    std::vector<int> kept;
    for (int i : order) {
      const int nr = base.normal_row[static_cast<size_t>(i)];
      if (nr < 0 || std::find(order.begin(), order.end(), nr) != order.end()) kept.push_back(i);
    }
    LcpProblem p = select_rows(base, kept);
    for (int k = 0; k < p.rows(); ++k)
      if (kept[static_cast<size_t>(k)] % 12 == 6) p.hi[k] = 0.5;  // contact c ≡ 3 (mod 6): hi finite
    // A zero row of J (A_ii = 0: the singular path), standard bounds, b > 0: complementary at 0.
    {
      LcpProblem z = p;
      const int n = p.rows() + 1;
      z.J.conservativeResize(n, p.J.cols());
      z.b.conservativeResize(n);
      z.lo.conservativeResize(n);
      z.hi.conservativeResize(n);
      z.mu.conservativeResize(n);
      z.b[n - 1] = 0.2;
      z.lo[n - 1] = 0.0;
      z.hi[n - 1] = INFINITY;
      z.mu[n - 1] = 0.0;
      z.normal_row.push_back(-1);
      std::vector<int> all(static_cast<size_t>(n));
      for (int k = 0; k < n; ++k) all[static_cast<size_t>(k)] = k;
      // Put the singular row in the middle of the sequence.
      std::rotate(all.begin() + n / 2, all.end() - 1, all.end());
      p = select_rows(z, all);
    }
    ASSERT_NO_THROW(p.validate());
    for (int k : {1, 10, 100}) {
      const SolveResult mf = run("pgs", p, k), as = run("pgs-assembled", p, k);
      ASSERT_EQ(mf.status, as.status) << mf.message << " | " << as.message;
      ASSERT_EQ(mf.sweeps, k);
      const double scale = std::max(1.0, max_abs(as.lambda));
      EXPECT_LE(max_abs(mf.lambda - as.lambda), 1e-10 * scale) << "seed " << seed << " sweeps " << k;
      ASSERT_EQ(mf.theta.size(), as.theta.size());
      for (size_t s = 0; s < mf.theta.size(); ++s) EXPECT_NEAR(mf.theta[s], as.theta[s], 1e-10 * scale);
      EXPECT_NE(mf.message.find("non-positive diagonal"), std::string::npos) << mf.message;
    }
  }
}

// An update that overflows is reported as Diverged in the same sweep by both forms, which
// return the last finite iterate (here λ⁰ = 0).
TEST(SolverPgs, MatrixFreeOverflowIsDivergedLikeAssembled) {
  test::TestRng rng(12);
  LcpProblem p = test::random_contact(10, 12, true, rng);
  p.b[4] = -1e307;  // λ_4 ← −b_4/A_44 overflows to +∞ in sweep 1
  for (const char* name : {"pgs", "pgs-assembled"}) {
    const SolveResult r = run(name, p, 10);
    EXPECT_EQ(r.status, SolveStatus::Diverged) << name << ": " << r.message;
    EXPECT_EQ(r.sweeps, 0) << name;
    EXPECT_TRUE(r.lambda.allFinite()) << name;
    EXPECT_EQ(max_abs(r.lambda), 0.0) << name;
  }
}

TEST(SolverPgs, PsorWithOmegaOneIsPgsAssembledBitForBit) {
  test::TestRng rng(3);
  const LcpProblem p = test::random_contact(30, 60, true, rng);
  const SolveResult a = run("pgs-assembled", p, 37), b = run("psor", p, 37, 0.0, {}, 1.0);
  EXPECT_EQ(a.lambda, b.lambda);
  EXPECT_EQ(a.theta, b.theta);
}

TEST(SolverPgs, FixedSweepModeRunsExactlyMaxSweeps) {
  test::TestRng rng(4);
  const LcpProblem p = test::random_contact(20, 30, true, rng);
  for (const char* name : {"pgs", "pgs-assembled", "psor", "jacobi"}) {
    const SolveResult r = run(name, p, 25, 0.0, {}, name == std::string("jacobi") ? 0.3 : 1.0);
    EXPECT_EQ(r.status, SolveStatus::SweepLimit) << name;
    EXPECT_EQ(r.sweeps, 25) << name;
    EXPECT_EQ(r.theta.size(), 25u) << name;
    EXPECT_TRUE(r.lambda.allFinite());
  }
}

TEST(SolverPgs, ToleranceModeStopsAtFirstSweepBelowTolerance) {
  test::TestRng rng(5);
  const LcpProblem p = test::random_contact(20, 30, true, rng);
  for (const char* name : {"pgs", "pgs-assembled"}) {
    const SolveResult r = run(name, p, 100000, 1e-8);
    ASSERT_EQ(r.status, SolveStatus::Converged) << name << ": " << r.message;
    ASSERT_EQ(static_cast<int>(r.theta.size()), r.sweeps);
    EXPECT_LE(r.theta.back(), 1e-8);
    for (int k = 0; k + 1 < r.sweeps; ++k) EXPECT_GT(r.theta[static_cast<size_t>(k)], 1e-8);
    EXPECT_LT(r.residual, 1e-5);
  }
}

TEST(SolverPgs, ThetaIsMaxChangePerSweep) {
  test::TestRng rng(6);
  const LcpProblem p = test::random_contact(20, 30, true, rng);
  const SolveResult r3 = run("pgs-assembled", p, 3), r4 = run("pgs-assembled", p, 4);
  EXPECT_DOUBLE_EQ(r4.theta[3], max_abs(r4.lambda - r3.lambda));
}

TEST(SolverPgs, CheckpointsSeeTheIterateOfThatSweep) {
  test::TestRng rng(7);
  const LcpProblem p = test::random_contact(20, 30, true, rng);
  for (const char* name : {"pgs", "pgs-assembled", "psor", "jacobi"}) {
    SolverOptions o;
    o.max_sweeps = 50;
    o.omega = name == std::string("jacobi") ? 0.3 : 1.0;
    o.record_theta = false;
    o.checkpoints = {1, 7, 7, 30, 50, 80};
    std::vector<std::pair<int, Eigen::VectorXd>> seen;
    o.on_checkpoint = [&](int k, const Eigen::VectorXd& l) { seen.emplace_back(k, l); };
    const SolveResult r = make_solver(name)->solve(p, Eigen::VectorXd(), o);
    EXPECT_TRUE(r.theta.empty());
    ASSERT_EQ(seen.size(), 4u) << name;  // 80 > max_sweeps; the duplicate 7 once
    for (const auto& [k, l] : seen) {
      SolverOptions ok = o;
      ok.max_sweeps = k;
      ok.on_checkpoint = nullptr;
      EXPECT_EQ(make_solver(name)->solve(p, Eigen::VectorXd(), ok).lambda, l) << name << " k=" << k;
    }
  }
}

TEST(SolverPgs, CheckpointsInAnyOrderSeeTheSameIterates) {
  // The cursor reads a strictly increasing list of positive checkpoints in place and copies,
  // sorts and cleans any other: a shuffled list with a duplicate, or one with non-positive
  // entries, sees what the increasing list sees, each checkpoint once.
  test::TestRng rng(7);
  const LcpProblem p = test::random_contact(20, 30, true, rng);
  const auto seen_with = [&](std::vector<int> ks) {
    SolverOptions o;
    o.max_sweeps = 50;
    o.record_theta = false;
    o.checkpoints = std::move(ks);
    std::vector<std::pair<int, Eigen::VectorXd>> seen;
    o.on_checkpoint = [&](int k, const Eigen::VectorXd& l) { seen.emplace_back(k, l); };
    (void)make_solver("pgs")->solve(p, Eigen::VectorXd(), o);
    return seen;
  };
  const auto sorted = seen_with({1, 7, 30, 50});
  ASSERT_EQ(sorted.size(), 4u);
  EXPECT_EQ(seen_with({30, 7, 50, 1, 7}), sorted);
  EXPECT_EQ(seen_with({-2, 0, 1, 7, 30, 50}), sorted);
  EXPECT_EQ(seen_with({1, 7, 7, 30, 50}), sorted);
  // Past a stop at the tolerance the checkpoints left see the final λ (flush_final), a
  // duplicate among them once too.
  SolverOptions o;
  o.max_sweeps = 200;
  o.tolerance = 1e9;  // [N]: the first sweep stops
  o.record_theta = false;
  o.checkpoints = {1, 150, 150, 180};
  std::vector<int> seen;
  o.on_checkpoint = [&](int k, const Eigen::VectorXd&) { seen.push_back(k); };
  const SolveResult r = make_solver("pgs")->solve(p, Eigen::VectorXd(), o);
  ASSERT_LT(r.sweeps, 150) << r.message;
  EXPECT_EQ(seen, (std::vector<int>{1, 150, 180}));
}

TEST(SolverPgs, WarmStartAtTheSolutionBarelyMoves) {
  test::TestRng rng(8);
  const LcpProblem p = test::random_contact(20, 30, true, rng);
  const SolveResult exact = run("newton", p, 3000);
  ASSERT_EQ(exact.status, SolveStatus::Converged) << exact.message;
  const SolveResult warm = run("pgs", p, 5, 0.0, exact.lambda), cold = run("pgs", p, 5);
  EXPECT_LT(warm.theta.front(), 1e-6 * cold.theta.front());
}

TEST(SolverPgs, MatrixFreeWithoutJacobianRunsTheAssembledForm) {
  test::TestRng rng(9);
  const LcpProblem p = test::random_contact(20, 30, true, rng);
  const SolveResult a = run("pgs", test::without_jacobian(p), 10), b = run("pgs-assembled", p, 10);
  EXPECT_EQ(a.lambda, b.lambda);
  EXPECT_NE(a.message.find("assembled"), std::string::npos);
  EXPECT_TRUE(make_solver("pgs")->needs_jacobian());
  EXPECT_FALSE(make_solver("pgs-assembled")->needs_jacobian());
}

TEST(SolverPgs, MatrixFreeRejectsRowsTouchingThreeBodies) {
  test::TestRng rng(10);
  LcpProblem p = test::random_contact(5, 4, false, rng);
  p.J.coeffRef(0, 0) += 0.1;
  p.J.coeffRef(0, 3) += 0.1;
  p.J.coeffRef(0, 6) += 0.1;
  p.J.coeffRef(0, 9) += 0.1;
  p.J.makeCompressed();
  const SolveResult r = run("pgs", p, 5);
  EXPECT_EQ(r.status, SolveStatus::InvalidInput);
  EXPECT_NE(r.message.find("two bodies"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace dc
