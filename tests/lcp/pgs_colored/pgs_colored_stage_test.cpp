// pgs-colored's staged packing (pgs_colored_layout.hpp, stage_sources): batches packed from the
// sources staged in the contacts' own order hold the bits of batches gathered from J, b and λ⁰
// in colour order, with wall contacts, contacts without friction and two-point manifolds mixed
// in, and name the same failures.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "lcp/solver_test_problems.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/pgs_colored_pack_simd.hpp"

namespace dc {
namespace {

struct Filled {
  colored::Prepared prep;
  std::vector<double> lp, other;
};

/// Every batch and pair batch of `prep` filled, staged from `from` ordered positions on.
Filled fill_all(const LcpProblem& p, const Eigen::VectorXd& l0, const colored::Prepared& laid, int from) {
  Filled f{laid, std::vector<double>(laid.row_of.size(), -7.0), std::vector<double>(laid.row_of.size(), -7.0)};
  colored::stage_sources(p, l0, f.prep, from);
  for (int bi = 0; bi < static_cast<int>(f.prep.batches.size()); ++bi)
    colored::fill_batch(p, l0, f.prep, bi, f.lp.data(), f.other.data());
  for (int pi = 0; pi < static_cast<int>(f.prep.pairs.size()); ++pi)
    colored::fill_pair(p, l0, f.prep, pi, f.lp.data(), f.other.data());
  return f;
}

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

void expect_same_batches(const Filled& a, const Filled& b, const std::string& what) {
  ASSERT_EQ(a.prep.batches.size(), b.prep.batches.size()) << what;
  for (size_t bi = 0; bi < a.prep.batches.size(); ++bi) {
    const colored::Batch& x = a.prep.batches[bi];
    const colored::Batch& y = b.prep.batches[bi];
    const bool same = same_bits(x.jn, y.jn) && same_bits(x.mjn, y.mjn) && same_bits(x.jt, y.jt) &&
                      same_bits(x.mjt, y.mjt) && same_bits(x.bn, y.bn) && same_bits(x.bt, y.bt) &&
                      same_bits(x.mu, y.mu) && same_bits(x.la, y.la) && same_bits(x.lb, y.lb) &&
                      same_bits(x.ka, y.ka) && same_bits(x.kb, y.kb) && x.count == y.count;
    EXPECT_TRUE(same) << what << ", batch " << bi;
  }
  EXPECT_EQ(0, std::memcmp(a.lp.data(), b.lp.data(), a.lp.size() * sizeof(double))) << what;
  EXPECT_EQ(0, std::memcmp(a.other.data(), b.other.data(), a.other.size() * sizeof(double))) << what;
  EXPECT_EQ(a.prep.row_of, b.prep.row_of) << what;
  EXPECT_EQ(a.prep.failed, b.prep.failed) << what;
}

TEST(PgsColoredStage, StagedBatchesAreTheGatheredOnesBitForBit) {
  if (!colored::simd_pack_available()) GTEST_SKIP() << "no AVX2";
  for (const int every : {0, 4}) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      test::TestRng rng(seed);
      LcpProblem p = test::random_contact(80, 400, true, rng, 0.5, every);
      Eigen::VectorXd l0(p.rows());
      for (int i = 0; i < p.rows(); ++i) l0[i] = rng.uniform(-1, 3);
      if (seed == 3) p.J.valuePtr()[p.J.outerIndexPtr()[p.constraints[7].normal_row]] = -0.0;  // r = 0 + (−0)
      ContactColorer colorer;
      colored::Prepared laid;
      ASSERT_EQ(colored::layout(p, colorer, nullptr, 1, laid), "");
      const Filled gathered = fill_all(p, l0, laid, 1 << 30);
      const Filled staged = fill_all(p, l0, laid, 0);
      EXPECT_FALSE(gathered.prep.staged_now);
      EXPECT_TRUE(staged.prep.staged_now);
      expect_same_batches(gathered, staged, "seed " + std::to_string(seed) + ", every " + std::to_string(every));
    }
  }
}

/// A singular contact (zero rows) is named alike by both packings.
TEST(PgsColoredStage, SingularContactIsNamedAlike) {
  if (!colored::simd_pack_available()) GTEST_SKIP() << "no AVX2";
  test::TestRng rng(5);
  LcpProblem p = test::random_contact(40, 120, true, rng, 0.5, 0);
  const int c = 17, row = p.constraints[c].normal_row;
  for (int q = p.J.outerIndexPtr()[row]; q < p.J.outerIndexPtr()[row + 1]; ++q) p.J.valuePtr()[q] = 0.0;
  const Eigen::VectorXd l0 = Eigen::VectorXd::Zero(p.rows());
  ContactColorer colorer;
  colored::Prepared laid;
  ASSERT_EQ(colored::layout(p, colorer, nullptr, 1, laid), "");
  const Filled gathered = fill_all(p, l0, laid, 1 << 30);
  const Filled staged = fill_all(p, l0, laid, 0);
  expect_same_batches(gathered, staged, "singular");
  EXPECT_NE(colored::first_failure(staged.prep), "");
  EXPECT_EQ(colored::first_failure(gathered.prep), colored::first_failure(staged.prep));
}

}  // namespace
}  // namespace dc
