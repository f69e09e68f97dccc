// GMRES from a start (gmres_from, gmres.hpp): newton-sparse's fresh run after a stale-factor run
// that ended at its cap starts from that run's answer. From a start within a few times the
// tolerance it reaches the same tolerance ‖b − K x‖ ≤ η‖b‖ in fewer iterations than from zero;
// a zero or unusable start gives gmres's bits.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstring>
#include <limits>

#include "lcp/solver_test_problems.hpp"
#include "solvers/newton_sparse/gmres.hpp"

namespace dc {
namespace {

/// K = S + E with S symmetric positive definite (n × n, spread spectrum) and E a non-symmetric
/// coupling of rank `rank`: the shape of newton-sparse's Newton system with sliding contacts.
struct StartSystem {
  Eigen::MatrixXd S, K;
  Eigen::VectorXd b;
};

StartSystem start_system(int n, int rank, uint64_t seed) {
  test::TestRng rng(seed);
  Eigen::MatrixXd G(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) G(i, j) = rng.uniform(-1, 1);
  StartSystem s;
  s.S = G * G.transpose() / n + 0.2 * Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd U(n, rank), W(n, rank);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < rank; ++j) {
      U(i, j) = rng.uniform(-1, 1);
      W(i, j) = rng.uniform(-1, 1);
    }
  s.K = s.S + (0.5 / n) * U * W.transpose();
  s.b.resize(n);
  for (int i = 0; i < n; ++i) s.b[i] = rng.uniform(-1, 1);
  return s;
}

bool start_same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

// A run preconditioned with S's diagonal alone, capped at a few iterations, ends above η (the
// failed stale run); gmres_from with the exact S⁻¹ from its answer reaches η in fewer iterations
// than gmres from zero with S⁻¹, and its true residual is at η.
TEST(NewtonSparseGmresStart, FreshRunFromAFailedRunsAnswerNeedsFewerIterations) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const StartSystem s = start_system(60, 40, seed + 4100);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(s.S);
    const Eigen::VectorXd diag = s.S.diagonal();
    const solvers::LinearMap K = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = s.K * in; };
    const solvers::LinearMap exact = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = ldlt.solve(in); };
    const solvers::LinearMap weak = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = in.cwiseQuotient(diag); };
    const double eta = 1e-8;
    Eigen::VectorXd from_zero;
    const solvers::KrylovOutcome zero = solvers::gmres(K, exact, s.b, from_zero, 30, 200, eta);
    // The capped run: S's diagonal as the (stale) preconditioner, then S⁻¹ for two thirds of the
    // iterations from zero; its answer is near, not at, η.
    Eigen::VectorXd start;
    solvers::gmres(K, weak, s.b, start, 30, 10, eta);
    const solvers::KrylovOutcome failed = solvers::gmres_from(K, exact, s.b, start, 30, 2 * zero.iterations / 3, eta);
    ASSERT_GT(failed.relative_residual, eta) << "seed " << seed;
    Eigen::VectorXd from_start = start;
    const solvers::KrylovOutcome warm = solvers::gmres_from(K, exact, s.b, from_start, 30, 200, eta);
    ASSERT_TRUE(zero.converged && warm.converged) << "seed " << seed;
    EXPECT_LT(warm.iterations, zero.iterations) << "seed " << seed;
    // The tolerance is relative to b (not to the start's residual), checked on the true residual.
    const double bnorm = s.b.norm();
    EXPECT_LE((s.b - s.K * from_start).norm(), 1.01 * eta * bnorm) << "seed " << seed;
    EXPECT_LE((s.b - s.K * from_zero).norm(), 1.01 * eta * bnorm) << "seed " << seed;
  }
}

// A start already at η: no iteration, x kept. A zero start, an empty one, a non-finite one and one
// worse than zero (‖b − K x‖ ≥ ‖b‖): gmres's result from zero, bit for bit.
TEST(NewtonSparseGmresStart, GoodStartIsKeptAndUnusableStartsGiveGmresBits) {
  const StartSystem s = start_system(40, 5, 4200);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(s.S);
  const solvers::LinearMap K = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = s.K * in; };
  const solvers::LinearMap P = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = ldlt.solve(in); };
  const double eta = 1e-6;
  Eigen::VectorXd reference;
  const solvers::KrylovOutcome ref = solvers::gmres(K, P, s.b, reference, 10, 100, eta, solvers::dot_in_lanes);
  ASSERT_TRUE(ref.converged);

  Eigen::VectorXd good = reference;
  const solvers::KrylovOutcome kept = solvers::gmres_from(K, P, s.b, good, 10, 100, eta, solvers::dot_in_lanes);
  EXPECT_TRUE(kept.converged);
  EXPECT_EQ(kept.iterations, 0);
  EXPECT_TRUE(start_same_bits(good, reference));

  const int n = static_cast<int>(s.b.size());
  Eigen::VectorXd non_finite = Eigen::VectorXd::Zero(n);
  non_finite[3] = std::numeric_limits<double>::quiet_NaN();
  for (Eigen::VectorXd x : {Eigen::VectorXd(Eigen::VectorXd::Zero(n)), Eigen::VectorXd(), non_finite,
                            Eigen::VectorXd(-1e3 * reference)}) {
    const solvers::KrylovOutcome o = solvers::gmres_from(K, P, s.b, x, 10, 100, eta, solvers::dot_in_lanes);
    EXPECT_EQ(o.iterations, ref.iterations);
    EXPECT_TRUE(start_same_bits(x, reference));
  }
}

}  // namespace
}  // namespace dc
