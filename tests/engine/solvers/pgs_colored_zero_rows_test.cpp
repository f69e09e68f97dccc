// pgs-colored's products skipping the rows with λ_i = 0 (pgs_colored_residual.hpp, skip_zero): Δu⁰
// and the closing natural residual keep the bits of the serial forms of lcp_problem.cpp (±0
// included) on every thread count, and a J with a non-finite entry turns the skip off, so a solve
// reports the residual lcp_problem.cpp computes for its λ.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_products.hpp"
#include "solvers/pgs_colored/pgs_colored_residual.hpp"
#include "bytes_equal.hpp"

namespace dc {
namespace {

int bodies_of(const LcpProblem& p) { return static_cast<int>((p.J.cols() + 2) / 3); }

/// λ with most rows +0 or −0 (as a resting pile's separated contacts have) and the rest random;
/// `every` = 3: a third of the rows nonzero (few bodies at rest), larger: most bodies at rest.
Eigen::VectorXd mostly_zero(int n, test::TestRng& rng, int every = 3) {
  Eigen::VectorXd l(n);
  for (int i = 0; i < n; ++i) l[i] = i % every == 0 ? rng.uniform(-1, 3) : (i % 2 == 0 ? 0.0 : -0.0);
  return l;
}

TEST(PgsColoredZeroRows, SkippingThemKeepsTheSerialBits) {
  test::TestRng rng(41);
  for (const bool friction : {false, true}) {
    for (const int every : {3, 40}) {
      const LcpProblem p = test::random_contact(every == 3 ? 30 : 120, 100, friction, rng, 0.5, 4);
      ASSERT_TRUE(colored::values_finite(p));
      const Eigen::VectorXd l = mostly_zero(p.rows(), rng, every);
      // Δu⁰ in the sweeps' layout against M⁻¹ (Jᵀλ) Δt as lcp_problem.cpp sums it
      const Eigen::VectorXd jt = p.J.transpose() * l;
      std::vector<double> du(static_cast<size_t>(colored::kStride) * (bodies_of(p) + 1), -1.0);
      Eigen::VectorXd scratch;
      colored::velocity_change(p, l, bodies_of(p), du.data(), scratch, true);
      for (int c = 0; c < jt.size(); ++c) {
        const double serial = p.inv_mass[c] * jt[c] * p.dt;
        EXPECT_EQ(0, std::memcmp(&serial, &du[static_cast<size_t>(colored::kStride * (c / 3) + c % 3)], sizeof serial))
            << "column " << c;
      }
      const double serial = natural_residual(p, l);
      for (int threads : {1, 2, 3}) {
        bool finite = false;
        const double r = colored::natural_residual(p, l, threads, scratch, finite, true);
        EXPECT_TRUE(finite);
        EXPECT_EQ(0, std::memcmp(&r, &serial, sizeof r)) << threads << " threads: " << r << " vs " << serial;
        Eigen::VectorXd column(3);
        colored::scaled_transpose_product(p, l, threads, column, true);
        Eigen::VectorXd want = jt;
        for (int c = 0; c < want.size(); ++c) want[c] = p.inv_mass[c] * want[c] * p.dt;
        ASSERT_EQ(column.size(), want.size());
        EXPECT_TRUE(test::bytes_equal(column, want)) << threads << " threads";
      }
    }
  }
}

/// A body whose Δu is zero in some entries only (a wall contact pushing straight up through its
/// centre: Δu = (0, v, 0)) is not at rest: its contacts' rows are read.
TEST(PgsColoredZeroRows, ABodyMovingAlongOneAxisIsNotAtRest) {
  test::TestRng rng(47);
  LcpProblem p = test::random_contact(20, 60, true, rng);
  p.b.setZero();
  int wall = -1;
  for (int c = 0; c < p.constraints.size() && wall < 0; ++c)
    if (!p.constraints[c].has_body_a()) wall = c;
  ASSERT_GE(wall, 0);
  const int n = p.constraints[wall].normal_row;
  double* v = p.J.valuePtr() + p.J.outerIndexPtr()[n];
  ASSERT_EQ(p.J.outerIndexPtr()[n + 1] - p.J.outerIndexPtr()[n], 3);
  v[0] = v[2] = 0.0;  // J_n = (0, n_y, 0)
  Eigen::VectorXd l = Eigen::VectorXd::Zero(p.rows());
  l[n] = 1.0;
  const double serial = natural_residual(p, l);
  ASSERT_GT(serial, 0.0);
  Eigen::VectorXd scratch;
  for (int threads : {1, 2}) {
    bool finite = false;
    const double r = colored::natural_residual(p, l, threads, scratch, finite, true);
    EXPECT_EQ(0, std::memcmp(&r, &serial, sizeof r)) << threads << " threads: " << r << " vs " << serial;
  }
}

TEST(PgsColoredZeroRows, ANonFiniteEntryOfJIsSeenAndTurnsTheSkipOff) {
  test::TestRng rng(43);
  LcpProblem p = test::random_contact(20, 60, true, rng);
  ASSERT_TRUE(colored::values_finite(p));
  const Eigen::VectorXd l = mostly_zero(p.rows(), rng);
  ASSERT_EQ(l[1], 0.0);
  p.J.valuePtr()[p.J.outerIndexPtr()[1]] = std::numeric_limits<double>::infinity();  // row 1 has λ = 0
  EXPECT_FALSE(colored::values_finite(p));
  // The serial form sees 0·∞ = NaN; a solve (which skips only when J is finite) reports it.
  EXPECT_EQ(natural_residual(p, l), std::numeric_limits<double>::infinity());
  PgsColoredDef d;
  d.threads = 1;
  SolverOptions o;
  o.max_sweeps = 0;
  const SolveResult r = make_pgs_colored(d)->solve(p, l, o);
  const double serial = natural_residual(p, r.lambda);
  EXPECT_EQ(0, std::memcmp(&r.residual, &serial, sizeof serial)) << r.residual << " vs " << serial;
  // An uncompressed J is checked row by row.
  LcpProblem u = test::random_contact(20, 60, true, rng);
  u.J.uncompress();
  EXPECT_TRUE(colored::values_finite(u));
  u.J.valuePtr()[u.J.outerIndexPtr()[7] + 1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(colored::values_finite(u));
}

TEST(PgsColoredZeroRows, AnInfiniteDiagonalIsRefusedByThePacking) {
  // Δu⁰ skips the rows with λ_i = 0 without testing J (it runs beside the packing), relying on
  // the packing's check that every A_ii is finite, which implies finite J entries. A finite J
  // entry large enough that A_ii = ∞ (1/A_ii = 0 is finite) must fail that check too: the solve
  // runs "pgs" (contacts with one body and with two).
  test::TestRng rng(53);
  const LcpProblem base = test::random_contact(20, 60, true, rng);
  for (int c = 0; c < base.constraints.size(); c += 7) {
    LcpProblem p = base;
    const int row = base.constraints[c].normal_row;
    p.J.valuePtr()[p.J.outerIndexPtr()[row]] = 1e200;
    ASSERT_TRUE(colored::values_finite(p));
    PgsColoredDef d;
    d.threads = 1;
    SolverOptions o;
    o.max_sweeps = 2;
    const SolveResult r = make_pgs_colored(d)->solve(p, Eigen::VectorXd::Zero(p.rows()), o);
    EXPECT_NE(r.message.find("ran pgs"), std::string::npos) << "contact " << c << ": " << r.message;
  }
}

}  // namespace
}  // namespace dc
