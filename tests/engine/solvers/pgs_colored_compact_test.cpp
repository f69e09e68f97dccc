// pgs-colored's compact layout (compact/compact_batch.hpp, PgsColoredDef::compact_layout): on the
// engine's problems every kernel sweeps the compact batches and gives the full layout's iterates,
// and so "pgs"'s, bit for bit; a problem whose coefficients do not follow from each other exactly
// (a non-isotropic M⁻¹, a hand-written J) keeps the full layout and still gives "pgs"'s iterates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "engine/fixed_sweeps.hpp"
#include "lcp/solver_test_problems.hpp"
#include "pgs_colored_kernels.hpp"
#include "solvers/pgs_colored/compact/compact_batch.hpp"
#include "solvers/pgs_colored/kernels/kernel_choice.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/pgs_colored_pack_simd.hpp"
#include "bytes_equal.hpp"

namespace dc {
namespace {

SolverOptions sweeps(int k, double omega = 1.0) {
  SolverOptions o = test::fixed_sweeps(k);
  o.record_theta = false;
  o.omega = omega;
  return o;
}

/// pgs-colored's solve of p with `d` (compact_layout as given), and whether it swept compact batches.
SolveResult solve(PgsColoredDef d, bool compact, const LcpProblem& p, const Eigen::VectorXd& l0,
                  const SolverOptions& o, bool& swept_compact) {
  PgsColoredProfile profile;
  d.compact_layout = compact;
  d.compact_from_batches = 0;  // (the test problems are small)
  d.profile = &profile;
  SolveResult r = make_pgs_colored(d)->solve(p, l0, o);
  EXPECT_TRUE(r.message.empty()) << r.message;  // the colour kernels ran, not the fallback
  swept_compact = profile.compact_solves > 0;
  return r;
}

/// Every kernel, compact and full layout: λ of "pgs" bit for bit (ω = 1), the compact layout's
/// iterates those of the full one (any ω); `compact_expected`: which layout the solver chose (1:
/// compact, 0: full, −1: not checked).
void expect_layouts_agree(const LcpProblem& p, int compact_expected, const std::string& what) {
  const Eigen::VectorXd l0 = test::mixed_sign_start(p);
  for (int k : {1, 7, 30})
    for (double omega : {1.0, 1.5}) {
      const SolveResult ref = make_solver("pgs")->solve(p, l0, sweeps(k));
      for (const PgsColoredDef& d : test::pgs_colored_kernel_defs()) {
        const std::string at = what + ", " + std::to_string(k) + " sweeps, ω " + std::to_string(omega) + ", " +
                               to_string(d.kernel);
        bool compact = false, full = true;
        const SolveResult c = solve(d, true, p, l0, sweeps(k, omega), compact);
        const SolveResult f = solve(d, false, p, l0, sweeps(k, omega), full);
        if (compact_expected >= 0) {
          EXPECT_EQ(compact, compact_expected == 1) << at;
        }
        EXPECT_FALSE(full) << at;
        test::expect_same_bits(c, f, at);
        if (omega != 1.0) continue;
        ASSERT_EQ(ref.lambda.size(), c.lambda.size());
        for (Eigen::Index i = 0; i < c.lambda.size(); ++i) ASSERT_EQ(ref.lambda[i], c.lambda[i]) << at << ", row " << i;
      }
    }
}

TEST(PgsColoredCompact, EngineProblemsSweepCompactBatchesWithTheIteratesOfPgs) {
  // The seed pile: single contacts with friction, walls (one-body contacts); frictionless
  // circles (lanes without a tangent row); a pyramid of circles of two masses; the box pyramid:
  // two-point manifolds (pair batches, not compacted) beside any single ones.
  expect_layouts_agree(test::settled_problem(stress::scaled_seed_pile(100), 100), 1, "pile");
  // Colours of many batches: the compact kernels' look-ahead (prefetches) runs inside them.
  expect_layouts_agree(test::settled_problem(stress::scaled_seed_pile(1000), 100), 1, "pile of 1,000");
  expect_layouts_agree(test::settled_problem(stress::friction_scene(0.0, 40), 60), 1, "frictionless");
  expect_layouts_agree(test::settled_problem(stress::pyramid_mass_ratio(10.0, true), 30), 1, "mass ratio");
  expect_layouts_agree(test::settled_problem(stress::box_pyramid(6), 20), -1, "box pyramid");
}

TEST(PgsColoredCompact, NonIsotropicInverseMassKeepsTheFullLayout) {
  // m⁻¹ of v_y ≠ m⁻¹ of v_x: the tangent's M⁻¹JᵀΔt is not the normal's turned, so no
  // batch with friction compresses exactly; a solve forced onto the compact layout would differ.
  LcpProblem p = test::settled_problem(stress::scaled_seed_pile(100), 100);
  for (Eigen::Index k = 1; k < p.inv_mass.size(); k += 3) p.inv_mass[k] *= 0.75;
  expect_layouts_agree(p, 0, "non-isotropic M⁻¹");
}

TEST(PgsColoredCompact, DirectPackingRefusesRowsWhoseBodyBEntriesAreNotDerivable) {
  // The pack writes the compact batches of single contacts with friction straight from J and
  // compares the derived coefficients in registers. Body b's J entry for v_x of one contact's
  // normal row scaled by 1 + 1e-9: alone, the tangent's M⁻¹JᵀΔt is then not the normal's
  // turned; with the tangent's entry for v_y (equal to it in the engine's form) scaled alike, that
  // still holds and only body b's J/A_ii, then not body a's negated, tells. Either must send the
  // whole solve to the full layout, with the iterates of "pgs".
  const LcpProblem settled = test::settled_problem(stress::scaled_seed_pile(100), 100);
  for (const bool both_rows : {false, true}) {
    LcpProblem p = settled;
    int changed = 0;
    for (int c = 0; c < p.constraints.size() && changed == 0; ++c) {
      const ContactConstraint& k = p.constraints[c];
      if (!k.has_body_a() || !k.has_friction()) continue;
      const int col = 3 * std::max(k.body_a, k.body_b);
      double& vn = p.J.coeffRef(k.normal_row, col);
      double& vt = p.J.coeffRef(k.tangent_row, col + 1);
      if (vn == 0.0 || vn != vt) continue;
      vn *= 1.0 + 1e-9;
      if (both_rows) vt = vn;
      ++changed;
    }
    ASSERT_EQ(changed, 1);
    expect_layouts_agree(p, 0, both_rows ? "body b's entries of both rows" : "body b's entry of the normal row");
  }
}

TEST(PgsColoredCompact, DirectPackingChecksTheStorageOfEveryRow) {
  // One two-body contact's normal row without body b's three entries (stored no more: the row
  // acts on body a alone, a valid problem): fewer entries than the direct packing reads, so it
  // must leave that batch to the general packing, which gives "pgs"'s λ bit for bit on every
  // kernel with the compact layout forced.
  LcpProblem p = test::settled_problem(stress::scaled_seed_pile(100), 100);
  p.structure.clear();  // (its structure is edited)
  int row = -1, from = -1;
  for (int c = 0; c < p.constraints.size() && row < 0; ++c) {
    const ContactConstraint& k = p.constraints[c];
    if (!k.has_body_a() || !k.has_friction()) continue;
    row = k.normal_row;
    from = std::max(k.body_a, k.body_b);
  }
  ASSERT_GE(row, 0);
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < p.J.outerSize(); ++i)
    for (SparseRowMatrix::InnerIterator it(p.J, i); it; ++it)
      if (i != row || it.col() / 3 != from) entries.emplace_back(i, static_cast<int>(it.col()), it.value());
  SparseRowMatrix pruned(p.J.rows(), p.J.cols());
  pruned.setFromTriplets(entries.begin(), entries.end());
  pruned.makeCompressed();
  p.J = pruned;
  const Eigen::VectorXd l0 = test::mixed_sign_start(p);
  const SolveResult ref = make_solver("pgs")->solve(p, l0, sweeps(7));
  for (PgsColoredDef d : test::pgs_colored_kernel_defs()) {
    d.compact_from_batches = 0;
    const SolveResult r = make_pgs_colored(d)->solve(p, l0, sweeps(7));
    EXPECT_TRUE(r.message.empty()) << to_string(d.kernel) << ": " << r.message;
    ASSERT_EQ(ref.lambda.size(), r.lambda.size());
    for (Eigen::Index i = 0; i < r.lambda.size(); ++i) ASSERT_EQ(ref.lambda[i], r.lambda[i]) << to_string(d.kernel);
  }
}

TEST(PgsColoredCompact, SmallProblemsKeepTheFullLayoutByDefault) {
  const LcpProblem p = test::settled_problem(stress::scaled_seed_pile(100), 100);
  PgsColoredProfile profile;
  PgsColoredDef d;
  d.profile = &profile;
  ASSERT_EQ(d.compact_from_batches, -1);
  const SolveResult a = make_pgs_colored(d)->solve(p, test::mixed_sign_start(p), sweeps(5));
  EXPECT_EQ(profile.compact_solves, 0);
  d.compact_from_batches = 1;
  test::expect_same_bits(a, make_pgs_colored(d)->solve(p, test::mixed_sign_start(p), sweeps(5)), "compact from 1 batch");
  EXPECT_EQ(profile.compact_solves, 1);
}

/// A square grid of side × side circles (r = 1) 1 mm apart on the floor: about 2·side² contacts
/// from one collision (no settling steps), the engine's rows.
LcpProblem compact_grid_problem(int side) {
  WorldDef d = stress::explicit_scene(2.001 * side + 1.0, 2.001 * side + 10.0);
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) d.body.push_back(stress::circle(1.0005 + 2.001 * i, 1.0005 + 2.001 * j));
  World world(d);
  world.collide();
  return world.assemble();
}

TEST(PgsColoredCompact, AutoTakesItsKernelForTheSizeOfEachSolveWithTheSameBits) {
  // The Auto kernel is chosen per solve (pgs_colored_auto_kernel(batches)): where it is the
  // AVX-512 one for large problems, they are swept in the compact layout (from 512 single
  // batches by default), small ones not, by one solver object in turn; every solve gives the
  // scalar kernel's bits.
  const LcpProblem large = compact_grid_problem(48), small = test::settled_problem(stress::scaled_seed_pile(100), 100);
  ASSERT_GE(large.constraints.size(), 8 * colored::kLargeFrom);
  const bool wide = pgs_colored_auto_kernel(large.constraints.size() / 8) == PgsColoredKernel::Avx512;
  PgsColoredProfile profile;
  PgsColoredDef d;
  d.profile = &profile;
  const auto solver = make_pgs_colored(d);
  PgsColoredDef scalar;
  scalar.kernel = PgsColoredKernel::Scalar;
  long compact = 0;
  for (const LcpProblem* p : {&large, &small, &large, &small}) {
    const Eigen::VectorXd l0 = test::mixed_sign_start(*p);
    const SolveResult r = solver->solve(*p, l0, sweeps(7));
    EXPECT_TRUE(r.message.empty()) << r.message;
    test::expect_same_bits(r, make_pgs_colored(scalar)->solve(*p, l0, sweeps(7)), "auto vs scalar");
    if (p == &large && wide) ++compact;
    EXPECT_EQ(profile.compact_solves, compact) << (p == &large ? "large" : "small");
  }
}

TEST(PgsColoredCompact, CompressionChecksEveryBit) {
  // A batch of the engine's form compresses and expands to the same bits; one changed bit of a
  // derived coefficient (slot 3 of a two-body lane, the tangent's M⁻¹JᵀΔt of a lane with
  // friction) is refused.
  colored::Batch B{};
  for (int k = 0; k < colored::W; ++k) {
    const double n[2] = {0.6 + 0.01 * k, -0.8}, ra = 0.3 * k - 1.0, rb = 0.25 - 0.1 * k, inv = 1.0 / (3.0 + k);
    const double im = 0.5 + k, ii = 2.0 + k, imb = 1.5, iib = 4.0, dt = 1.0 / 60.0;
    const double rn[6] = {0.0 + n[0], 0.0 + n[1], ra, 0.0 - n[0], 0.0 - n[1], rb};
    const double rt[6] = {0.0 - n[1], 0.0 + n[0], rb, 0.0 + n[1], 0.0 - n[0], ra};
    const double ims[6] = {im, im, ii, imb, imb, iib};
    for (int s = 0; s < 6; ++s) {
      B.jn[s][k] = rn[s] * inv;
      B.jt[s][k] = rt[s] * (2.0 * inv);
      B.mjn[s][k] = (rn[s] * ims[s]) * dt;
      B.mjt[s][k] = (rt[s] * ims[s]) * dt;
    }
    B.bn[k] = 0.1 * k;
    B.mu[k] = 0.5;
    B.la[k] = 4 * k;
    B.lb[k] = 4 * (k + 8);
    B.ka[k] = B.kb[k] = 1;
  }
  B.count = colored::W;
  colored::CompactBatch C;
  ASSERT_TRUE(colored::compress(B, C));
  colored::Batch E{};
  colored::expand(C, E);
  EXPECT_EQ(std::memcmp(E.jn, B.jn, sizeof(B.jn)), 0);
  EXPECT_EQ(std::memcmp(E.mjt, B.mjt, sizeof(B.mjt)), 0);
  for (auto mutate : {+[](colored::Batch& b) { b.jn[3][2] = std::nextafter(b.jn[3][2], 1.0); },
                      +[](colored::Batch& b) { b.jt[4][5] = -b.jt[4][5]; },
                      +[](colored::Batch& b) { b.mjt[1][0] *= 1.0 + 1e-15; },
                      +[](colored::Batch& b) { b.mjt[3][7] = 0.0; }}) {
    colored::Batch m = B;
    mutate(m);
    EXPECT_FALSE(colored::compress(m, C));
  }
}

/// Every single-contact batch of `laid` packed by fill_compact (ω, the AVX-512 pack when `wide`),
/// the sources staged (stage_sources) from `from` ordered positions on.
struct CompactFill {
  colored::Prepared prep;
  std::vector<double> lp, other;
  std::vector<int> direct;  // per batch: 1 when it went to the compact layout
};
CompactFill fill_compact_all(const LcpProblem& p, const Eigen::VectorXd& l0, const colored::Prepared& laid, int from,
                             bool wide, double omega) {
  CompactFill f{laid, std::vector<double>(laid.row_of.size(), -7.0), std::vector<double>(laid.row_of.size(), -7.0), {}};
  f.prep.wide_pack = wide;
  f.prep.compact.resize(f.prep.batches.size());
  colored::stage_sources(p, l0, f.prep, from);
  for (int bi = 0; bi < static_cast<int>(f.prep.batches.size()); ++bi)
    f.direct.push_back(colored::fill_compact(p, l0, f.prep, bi, f.lp.data(), f.other.data(), omega, false) ? 1 : 0);
  return f;
}

template <class T>
bool same_bytes(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

TEST(PgsColoredCompact, StagedSourcesPackTheGatheredCompactBatchesBitForBit) {
  // Problems past kStageFrom ordered positions stage their sources (stage_sources) and pack the
  // compact batches straight from the staged records: the same batches, λ⁰, A_ii and rows as
  // packed from J, b and λ⁰, on the AVX2 and the AVX-512 pack, with and without over-relaxation.
  if (!colored::simd_pack_available()) GTEST_SKIP() << "no AVX2";
  const std::pair<const char*, LcpProblem> problems[] = {
      {"pile", test::settled_problem(stress::scaled_seed_pile(300), 100)},
      {"mass ratio", test::settled_problem(stress::pyramid_mass_ratio(10.0, true), 30)},
      {"frictionless", test::settled_problem(stress::friction_scene(0.0, 40), 60)}};
  for (const auto& [what, p] : problems) {
    const Eigen::VectorXd l0 = test::mixed_sign_start(p);
    ContactColorer colorer;
    colored::Prepared laid;
    ASSERT_EQ(colored::layout(p, colorer, nullptr, 1, laid, nullptr, false), "") << what;
    for (const bool wide : {false, true})
      for (const double omega : {1.0, 1.5}) {
        if (wide && !colored::cpu_has_avx512()) continue;
        const std::string at = std::string(what) + (wide ? ", AVX-512" : ", AVX2") + ", ω " + std::to_string(omega);
        const CompactFill g = fill_compact_all(p, l0, laid, 1 << 30, wide, omega);
        const CompactFill s = fill_compact_all(p, l0, laid, 0, wide, omega);
        ASSERT_FALSE(g.prep.staged_now);
        ASSERT_TRUE(s.prep.staged_now);
        ASSERT_EQ(g.direct, s.direct) << at;
        for (size_t bi = 0; bi < g.direct.size(); ++bi) {
          if (g.direct[bi] == 0) {
            const colored::Batch &x = g.prep.batches[bi], &y = s.prep.batches[bi];
            EXPECT_TRUE(same_bytes(x.jn, y.jn) && same_bytes(x.mjn, y.mjn) && same_bytes(x.jt, y.jt) &&
                        same_bytes(x.mjt, y.mjt) && same_bytes(x.bn, y.bn) && same_bytes(x.bt, y.bt) &&
                        same_bytes(x.mu, y.mu) && same_bytes(x.la, y.la) && same_bytes(x.lb, y.lb) && x.count == y.count)
                << at << ", full batch " << bi;
            continue;
          }
          const colored::CompactBatch &x = g.prep.compact[bi], &y = s.prep.compact[bi];
          EXPECT_TRUE(same_bytes(x.jn, y.jn) && same_bytes(x.jt, y.jt) && same_bytes(x.mjn, y.mjn) &&
                      same_bytes(x.mjt, y.mjt) && same_bytes(x.bn, y.bn) && same_bytes(x.bt, y.bt) &&
                      same_bytes(x.mu, y.mu) && same_bytes(x.la, y.la) && same_bytes(x.lb, y.lb) &&
                      same_bytes(x.ka, y.ka) && same_bytes(x.kb, y.kb) && x.two == y.two && x.fric == y.fric &&
                      x.count == y.count)
              << at << ", compact batch " << bi;
        }
        EXPECT_TRUE(test::bytes_equal(g.lp, s.lp)) << at;
        EXPECT_TRUE(test::bytes_equal(g.other, s.other)) << at;
        EXPECT_TRUE(test::bytes_equal(g.prep.diag, s.prep.diag)) << at;
        EXPECT_EQ(g.prep.row_of, s.prep.row_of) << at;
        EXPECT_EQ(g.prep.failed, s.prep.failed) << at;
        if (std::string(what) != "frictionless") {  // (lanes without friction are packed full)
          EXPECT_GT(std::count(s.direct.begin(), s.direct.end(), 1), 0) << at;
        }
      }
  }
}

}  // namespace
}  // namespace dc
