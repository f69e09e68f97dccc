// prox-newton's body-space H = W⁻¹ + Jᵀ D J built into J's fixed pattern (NormalMatrix) is
// Eigen's sparse product `Jt * (D.asDiagonal() * J) + diag(W⁻¹)` entry by entry: the same
// pattern and the same bits, on a pile (floor rows touch one body), on random contacts with a
// static body (M⁻¹ = 0, W⁻¹ = 1e300) and wall rows, and across repeated assemble() calls with
// other D (the values are rebuilt, not accumulated) and problems (the pattern is rebuilt).
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/body/normal_matrix.hpp"
#include "solvers/prox_newton/body_metric.hpp"

namespace dc {
namespace {

SparseRowMatrix eigen_normal_matrix(const LcpProblem& p, const Eigen::VectorXd& winv, const Eigen::VectorXd& d) {
  const SparseRowMatrix Jt(p.J.transpose());
  SparseRowMatrix Wd(winv.size(), winv.size());
  Wd.setIdentity();
  Wd.diagonal() = winv;
  const SparseRowMatrix DJ = d.asDiagonal() * p.J;
  SparseRowMatrix H = Jt * DJ;
  H += Wd;
  H.makeCompressed();
  return H;
}

/// Row weights as BodyNewton's D: 1/δ on about half the rows, 0 elsewhere; with `general`, any
/// positive weight on the other half instead of 0.
Eigen::VectorXd random_weights(int n, test::TestRng& rng, bool general) {
  Eigen::VectorXd d(n);
  for (int i = 0; i < n; ++i) d[i] = rng.uniform() < 0.5 ? 1e4 : (general ? rng.uniform(1, 1e5) : 0.0);
  return d;
}

void expect_same_bits(const SparseRowMatrix& a, const SparseRowMatrix& b) {
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.nonZeros(), b.nonZeros());
  for (Eigen::Index i = 0; i <= a.rows(); ++i) ASSERT_EQ(a.outerIndexPtr()[i], b.outerIndexPtr()[i]) << i;
  for (Eigen::Index k = 0; k < a.nonZeros(); ++k) {
    ASSERT_EQ(a.innerIndexPtr()[k], b.innerIndexPtr()[k]) << k;
    ASSERT_EQ(std::bit_cast<uint64_t>(a.valuePtr()[k]), std::bit_cast<uint64_t>(b.valuePtr()[k]))
        << "entry " << k << ": " << a.valuePtr()[k] << " vs " << b.valuePtr()[k];
  }
}

void check_problem(const LcpProblem& p, test::TestRng& rng, solvers::prox::NormalMatrix& h) {
  SparseRowMatrix Jt, Wd;
  Eigen::VectorXd w, winv;
  double max_diag = 0.0;
  bind_body_metric(p, Jt, w, winv, Wd, max_diag);
  h.bind(p.J, Jt);
  for (int round = 0; round < 4; ++round) {
    const Eigen::VectorXd d = random_weights(p.rows(), rng, round % 2 == 1);
    h.assemble(p.J, winv, d);
    expect_same_bits(h.matrix(), eigen_normal_matrix(p, winv, d));
  }
}

TEST(ProxNewtonNormalMatrix, PileMatchesEigenProductBits) {
  test::TestRng rng(2101);
  solvers::prox::NormalMatrix h;
  check_problem(test::deep_pile(6, 5, 0.5), rng, h);
}

TEST(ProxNewtonNormalMatrix, StaticBodyAndWallRowsMatchEigenProductBits) {
  solvers::prox::NormalMatrix h;  // bound to each problem in turn: its kept storage is rebuilt
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 2100);
    LcpProblem p = test::random_contact(20, 40, true, rng, 0.4);
    p.inv_mass.segment(0, 3).setZero();  // body 0 static: W⁻¹ = 1e300 on its dofs
    check_problem(p, rng, h);
  }
}

}  // namespace
}  // namespace dc
