// pgs-colored's Δu⁰ with the finiteness test of J folded into its pass (pgs_colored_products.hpp,
// velocity_change_checked; pgs_colored_residual.hpp, transpose_rows_checked): the bits of the
// two-pass form (values_finite, then velocity_change skipping the λ_i = 0 rows only when J is
// finite), and the sums of J's rows in row order whatever J's storage (repeated or unsorted
// columns).
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_products.hpp"
#include "solvers/pgs_colored/pgs_colored_residual.hpp"

namespace dc {
namespace {

int bodies_of(const LcpProblem& p) { return static_cast<int>((p.J.cols() + 2) / 3); }

/// λ with rows +0, −0 and random values (every `every`-th row nonzero).
Eigen::VectorXd mostly_zero(int n, test::TestRng& rng, int every) {
  Eigen::VectorXd l(n);
  for (int i = 0; i < n; ++i) l[i] = i % every == 0 ? rng.uniform(-1, 3) : (i % 2 == 0 ? 0.0 : -0.0);
  return l;
}

/// out[c] += J_ic·λ_i row after row, each row's entries in storage order: the order every form
/// of Jᵀλ keeps (Eigen's row-major scatter).
std::vector<double> naive_transpose(const LcpProblem& p, const Eigen::VectorXd& l) {
  std::vector<double> out(static_cast<size_t>(p.J.cols()), 0.0);
  const int* outer = p.J.outerIndexPtr();
  const int* nnz = p.J.innerNonZeroPtr();
  for (int i = 0; i < p.rows(); ++i) {
    const int q1 = nnz != nullptr ? outer[i] + nnz[i] : outer[i + 1];
    for (int q = outer[i]; q < q1; ++q) out[static_cast<size_t>(p.J.innerIndexPtr()[q])] += p.J.valuePtr()[q] * l[i];
  }
  return out;
}

/// The checked Δu⁰ against the two-pass form, bit for bit, and j_finite against values_finite.
void expect_same_du(const LcpProblem& p, const Eigen::VectorXd& l, const std::string& what) {
  const int bodies = bodies_of(p);
  const size_t size = static_cast<size_t>(colored::kStride) * (bodies + 1);
  std::vector<double> want(size, -1.0), got(size, -2.0);
  Eigen::VectorXd jt_want, jt_got;
  const bool finite = colored::values_finite(p);
  const bool ok_want = colored::velocity_change(p, l, bodies, want.data(), jt_want, finite);
  bool j_finite = !finite;
  const bool ok_got = colored::velocity_change_checked(p, l, bodies, got.data(), jt_got, j_finite);
  EXPECT_EQ(j_finite, finite) << what;
  EXPECT_EQ(ok_got, ok_want) << what;
  EXPECT_EQ(0, std::memcmp(got.data(), want.data(), sizeof(double) * size)) << what;
  const std::vector<double> naive = naive_transpose(p, l);
  ASSERT_EQ(static_cast<size_t>(jt_got.size()), naive.size()) << what;
  EXPECT_EQ(0, std::memcmp(jt_got.data(), naive.data(), sizeof(double) * naive.size())) << what;
}

TEST(PgsColoredDu0, CheckedPassKeepsTheTwoPassBits) {
  test::TestRng rng(71);
  for (const bool friction : {false, true}) {
    for (const int every : {1, 3, 40}) {
      // 400 contacts: rows in several chunks of the list (256 rows each)
      const LcpProblem p = test::random_contact(150, 400, friction, rng, 0.5, 4);
      expect_same_du(p, mostly_zero(p.rows(), rng, every),
                     std::string(friction ? "friction" : "frictionless") + ", every " + std::to_string(every));
    }
  }
}

TEST(PgsColoredDu0, ANonFiniteEntryInOneChunkTurnsTheSkipOffThere) {
  test::TestRng rng(73);
  for (const bool compressed : {true, false}) {
    LcpProblem p = test::random_contact(150, 400, true, rng, 0.5, 4);
    if (!compressed) p.J.uncompress();
    const Eigen::VectorXd l = mostly_zero(p.rows(), rng, 3);
    const int row = 301;  // in the second chunk, λ = 0
    ASSERT_GT(p.rows(), 512);
    ASSERT_EQ(l[row], 0.0);
    p.J.valuePtr()[p.J.outerIndexPtr()[row] + 1] = std::numeric_limits<double>::infinity();
    ASSERT_FALSE(colored::values_finite(p));
    expect_same_du(p, l, compressed ? "compressed" : "uncompressed");
    // 0·∞ = NaN reaches Δu⁰ as in the product without the skip
    std::vector<double> du(static_cast<size_t>(colored::kStride) * (bodies_of(p) + 1));
    Eigen::VectorXd jt;
    bool j_finite = true;
    EXPECT_FALSE(colored::velocity_change_checked(p, l, bodies_of(p), du.data(), jt, j_finite));
    EXPECT_FALSE(j_finite);
  }
}

TEST(PgsColoredDu0, RowsWithARepeatedOrUnsortedColumnKeepRowOrder) {
  test::TestRng rng(79);
  for (int trial = 0; trial < 20; ++trial) {
    LcpProblem p = test::random_contact(30, 80, true, rng, 0.5, 4);
    // every contact's rows (normal, tangent: the same columns) get a repeated column, or a swapped
    // pair: each column's terms still come in row order, each row's in storage order
    int* inner = p.J.innerIndexPtr();
    const int* outer = p.J.outerIndexPtr();
    for (int c = 0; c < p.constraints.size(); ++c) {
      const ContactConstraint& k = p.constraints[c];
      if (!k.has_friction()) continue;
      for (const int i : {k.normal_row, k.tangent_row}) {
        int* col = inner + outer[i];
        if (trial % 2 == 0)
          col[1] = col[0];  // repeated column
        else
          std::swap(col[0], col[2]);  // unsorted
      }
    }
    Eigen::VectorXd l(p.rows());
    for (int i = 0; i < p.rows(); ++i) l[i] = rng.uniform(-1, 3);
    Eigen::VectorXd jt = Eigen::VectorXd::Zero(p.J.cols());
    EXPECT_TRUE(colored::transpose_rows_checked(p, l.data(), jt.data()));
    const std::vector<double> naive = naive_transpose(p, l);
    EXPECT_EQ(0, std::memcmp(jt.data(), naive.data(), sizeof(double) * naive.size())) << "trial " << trial;
    Eigen::VectorXd plain = Eigen::VectorXd::Zero(p.J.cols());
    colored::transpose_rows(p, l.data(), 0, p.rows(), 0, static_cast<int>(p.J.cols()), plain.data());
    EXPECT_EQ(0, std::memcmp(plain.data(), naive.data(), sizeof(double) * naive.size())) << "trial " << trial;
  }
}

}  // namespace
}  // namespace dc
