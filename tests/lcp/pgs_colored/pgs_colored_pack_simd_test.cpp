// pgs-colored's 8-lane row packing (pgs_colored_pack_simd.hpp) against pack_row's scalar formula
// written out here lane by lane (r = 0 + J_is, m = r·M⁻¹·Δt, A_ii = Σ r·m in slot order,
// j = r·(1/A_ii), b = b_i·(1/A_ii), zeros in absent slots): the same bits, on contact rows with
// one and two bodies, −0 entries and singular rows; rows stored otherwise are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "lcp/solver_test_problems.hpp"
#include "solvers/pgs_colored/pgs_colored_pack_simd.hpp"

namespace dc {
namespace {

using colored::W;

struct Packed {
  alignas(64) double j[6][W], mj[6][W], b[W], diag[W];
  unsigned singular = 0;
};

/// The scalar formula for the rows rows[0..W) on the bodies at columns a[k], bb[k].
Packed reference(const LcpProblem& p, const int* rows, const int* a, const int* bb) {
  Packed out;
  for (int lane = 0; lane < W; ++lane) {
    double r[6] = {0, 0, 0, 0, 0, 0};
    for (SparseRowMatrix::InnerIterator it(p.J, rows[lane]); it; ++it) {
      const int c = static_cast<int>(it.col());
      r[c >= a[lane] && c < a[lane] + 3 ? c - a[lane] : 3 + c - bb[lane]] = 0.0 + it.value();
    }
    double d = 0.0;
    double m[6];
    for (int s = 0; s < 6; ++s) {
      const int col = s < 3 ? a[lane] + s : bb[lane] + s - 3;
      m[s] = s >= 3 && bb[lane] < 0 ? 0.0 : r[s] * p.inv_mass[col] * p.dt;
      if (s < 3 || bb[lane] >= 0) d += r[s] * m[s];
    }
    const double inv = 1.0 / d;
    for (int s = 0; s < 6; ++s) {
      out.j[s][lane] = r[s] * inv;
      out.mj[s][lane] = m[s];
    }
    out.b[lane] = p.b[rows[lane]] * inv;
    out.diag[lane] = d;
    if (!(d > 0 && std::isfinite(inv))) out.singular |= 1u << lane;
  }
  return out;
}

/// Packs contacts first..first+W−1 (mod the count), normal or tangent rows, both ways; false
/// when pack_rows_simd refused them.
bool pack_both(const LcpProblem& p, int first, bool tangent, Packed& simd, Packed& ref) {
  int rows[W], a[W], bb[W];
  for (int lane = 0; lane < W; ++lane) {
    const ContactConstraint& k = p.constraints[(first + lane) % p.constraints.size()];
    const int lo = k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b;
    const int hi = k.has_body_a() ? std::max(k.body_a, k.body_b) : -1;
    rows[lane] = tangent ? k.tangent_row : k.normal_row;
    a[lane] = 3 * lo;
    bb[lane] = hi < 0 ? -1 : 3 * hi;
  }
  ref = reference(p, rows, a, bb);
  return colored::pack_rows_simd(p, rows, a, bb, simd.j, simd.mj, simd.b, simd.diag, simd.singular);
}

void expect_same_bits(const Packed& x, const Packed& y, const char* what) {
  EXPECT_EQ(std::memcmp(x.j, y.j, sizeof x.j), 0) << what;
  EXPECT_EQ(std::memcmp(x.mj, y.mj, sizeof x.mj), 0) << what;
  EXPECT_EQ(std::memcmp(x.b, y.b, sizeof x.b), 0) << what;
  EXPECT_EQ(std::memcmp(x.diag, y.diag, sizeof x.diag), 0) << what;
  EXPECT_EQ(x.singular, y.singular) << what;
}

TEST(PgsColoredPackSimd, SameBitsAsTheScalarFormula) {
  if (!colored::simd_pack_available()) GTEST_SKIP() << "no AVX2";
  test::TestRng rng(11);
  LcpProblem p = test::random_contact(40, 120, true, rng);  // every 5th contact on a wall
  // −0 entries (0 + −0 = +0 in r) and a row of zeros (A_ii = 0: singular, j = 0·∞ = NaN).
  double* v = p.J.valuePtr();
  for (int q = 0; q < p.J.nonZeros(); q += 7) v[q] = -0.0;
  const int zero_row = p.constraints[9].normal_row;
  for (SparseRowMatrix::InnerIterator it(p.J, zero_row); it; ++it) it.valueRef() = 0.0;
  int singular_batches = 0;
  for (int first = 0; first < p.constraints.size(); first += 3) {
    for (const bool tangent : {false, true}) {
      Packed simd, ref;
      ASSERT_TRUE(pack_both(p, first, tangent, simd, ref)) << "contacts from " << first;
      expect_same_bits(simd, ref, tangent ? "tangent rows" : "normal rows");
      singular_batches += simd.singular != 0 ? 1 : 0;
    }
  }
  EXPECT_GT(singular_batches, 0);
}

TEST(PgsColoredPackSimd, RowsStoredOtherwiseAreRefused) {
  if (!colored::simd_pack_available()) GTEST_SKIP() << "no AVX2";
  test::TestRng rng(5);
  const LcpProblem p = test::random_contact(20, 40, true, rng);
  int rows[W], a[W], bb[W];
  for (int lane = 0; lane < W; ++lane) {
    const ContactConstraint& k = p.constraints[lane];
    rows[lane] = k.normal_row;
    a[lane] = 3 * (k.has_body_a() ? std::min(k.body_a, k.body_b) : k.body_b);
    bb[lane] = k.has_body_a() ? 3 * std::max(k.body_a, k.body_b) : -1;
  }
  Packed out;
  ASSERT_TRUE(colored::pack_rows_simd(p, rows, a, bb, out.j, out.mj, out.b, out.diag, out.singular));
  a[3] += 3;  // lane 3's row acts on other columns than the ones given
  EXPECT_FALSE(colored::pack_rows_simd(p, rows, a, bb, out.j, out.mj, out.b, out.diag, out.singular));
}

}  // namespace
}  // namespace dc
