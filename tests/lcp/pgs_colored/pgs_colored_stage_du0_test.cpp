// pgs-colored's Δu⁰ product summed in the staging pass (pgs_colored_layout.hpp, stage_sources
// with jt): Jᵀλ⁰ and Δu⁰ hold velocity_change's bits (λ⁰ with zeros of both signs, wall
// contacts, contacts without friction), and the pass declines (returns false) when its sum
// would not be velocity_change's: rows out of contact order, a non-finite J entry. A serial
// solve (which sums Δu⁰ in the staging pass) returns the λ bits of a threaded one (which does not).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "dc/lcp/pgs_colored.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/pgs_colored_pack_simd.hpp"
#include "solvers/pgs_colored/pgs_colored_products.hpp"

namespace dc {
namespace {

bool same_bits(const double* a, const double* b, long n) { return std::memcmp(a, b, sizeof(double) * n) == 0; }

/// λ⁰ with a third of its entries +0 or −0 and the rest of either sign.
Eigen::VectorXd lambda_with_zeros(int n, test::TestRng& rng) {
  Eigen::VectorXd l(n);
  for (int i = 0; i < n; ++i) {
    const int kind = rng.below(6);
    l[i] = kind == 0 ? 0.0 : kind == 1 ? -0.0 : rng.uniform(-1, 3);
  }
  return l;
}

/// stage_sources with jt on p (every problem staged: from = 0); its verdict, jt and the Δu of
/// scale_velocity.
struct Fused {
  bool ok = false;
  Eigen::VectorXd jt;
  std::vector<double> du;
};
Fused fused(const LcpProblem& p, const Eigen::VectorXd& l0, int bodies) {
  ContactColorer colorer;
  colored::Prepared prep;
  EXPECT_EQ(colored::layout(p, colorer, nullptr, 1, prep), "");
  Fused f;
  f.jt = Eigen::VectorXd::Constant(p.J.cols(), 5.0);  // stale values: the pass starts from 0
  f.ok = colored::stage_sources(p, l0, prep, 0, f.jt.data());
  EXPECT_TRUE(prep.staged_now);
  f.du.assign(static_cast<size_t>(colored::kStride) * (bodies + 1), -9.0);
  if (f.ok) colored::scale_velocity(p, f.jt, bodies, f.du.data());
  return f;
}

TEST(PgsColoredStageDu0, JtAndDuAreVelocityChangesBitForBit) {
  if (!colored::simd_pack_available()) GTEST_SKIP() << "no AVX2";
  for (const int every : {0, 3}) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      test::TestRng rng(seed);
      const int bodies = 60;
      const LcpProblem p = test::random_contact(bodies, 500, true, rng, 0.5, every);
      const Eigen::VectorXd l0 = lambda_with_zeros(p.rows(), rng);
      const Fused f = fused(p, l0, bodies);
      ASSERT_TRUE(f.ok) << "seed " << seed;
      Eigen::VectorXd jt;
      std::vector<double> du(f.du.size(), -9.0);
      colored::velocity_change(p, l0, bodies, du.data(), jt);
      ASSERT_EQ(jt.size(), f.jt.size());
      EXPECT_TRUE(same_bits(jt.data(), f.jt.data(), jt.size())) << "seed " << seed << ", every " << every;
      EXPECT_TRUE(same_bits(du.data(), f.du.data(), static_cast<long>(du.size())))
          << "seed " << seed << ", every " << every;
    }
  }
}

TEST(PgsColoredStageDu0, DeclinesRowsOutOfContactOrder) {
  if (!colored::simd_pack_available()) GTEST_SKIP() << "no AVX2";
  test::TestRng rng(7);
  LcpProblem p = test::random_contact(40, 200, true, rng, 0.5, 0);
  ContactConstraints reversed;  // the same contacts, last first: valid, rows descending
  for (int c = p.constraints.size() - 1; c >= 0; --c) reversed.add(p.constraints[c]);
  p.constraints = reversed;
  ASSERT_NO_THROW(p.validate());
  EXPECT_FALSE(fused(p, lambda_with_zeros(p.rows(), rng), 40).ok);
}

TEST(PgsColoredStageDu0, DeclinesANonFiniteJEntry) {
  if (!colored::simd_pack_available()) GTEST_SKIP() << "no AVX2";
  for (const double bad : {INFINITY, NAN}) {
    test::TestRng rng(9);
    LcpProblem p = test::random_contact(40, 200, true, rng, 0.5, 0);
    const int row = p.constraints[150].tangent_row;
    p.J.valuePtr()[p.J.outerIndexPtr()[row] + 1] = bad;
    Eigen::VectorXd l0 = lambda_with_zeros(p.rows(), rng);
    l0[row] = 0.0;  // skipped by velocity_change's chunks of finite rows, not by the fused sum
    EXPECT_FALSE(fused(p, l0, 40).ok) << bad;
  }
}

/// A problem large enough to be staged by the solver (colored::kStageFrom ordered positions):
/// the serial solve sums Δu⁰ in the staging pass, the threaded one (forced) by its own product.
TEST(PgsColoredStageDu0, SerialSolveIsTheThreadedOnesBits) {
  if (!colored::simd_pack_available()) GTEST_SKIP() << "no AVX2";
  test::TestRng rng(11);
  const LcpProblem p = test::random_contact(3000, colored::kStageFrom + 500, true, rng, 0.5, 5);
  const Eigen::VectorXd l0 = lambda_with_zeros(p.rows(), rng).cwiseAbs();
  SolverOptions o;
  o.max_sweeps = 4;
  o.tolerance = 0;
  PgsColoredDef serial, threaded;
  threaded.threads = 2;
  threaded.min_batches_per_thread = 0;
  const SolveResult a = make_pgs_colored(serial)->solve(p, l0, o);
  const SolveResult b = make_pgs_colored(threaded)->solve(p, l0, o);
  ASSERT_TRUE(a.message.empty()) << a.message;
  ASSERT_EQ(a.lambda.size(), b.lambda.size());
  EXPECT_TRUE(same_bits(a.lambda.data(), b.lambda.data(), a.lambda.size()));
  EXPECT_EQ(a.residual, b.residual);
}

}  // namespace
}  // namespace dc
