// pgs-colored's pack on the team (setup/team_pack.hpp): the parts hand out every batch exactly once
// in member-major blocks of each colour range, and the packed problem (compact or full batches,
// pair batches, rows, A_ii, the permuted λ⁰, the failures) is the same bytes on 1, 2 and 3
// threads, the sources staged or gathered, with and without over-relaxation.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "dc/engine/stress_scenes.hpp"
#include "lcp/solver_test_problems.hpp"
#include "pgs_colored_kernels.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/pgs_colored_pack_simd.hpp"
#include "solvers/pgs_colored/setup/team_pack.hpp"
#include "bytes_equal.hpp"

namespace dc {
namespace {

/// Which part holds each job of pack_parts(ranges, batches, threads, chunk), −1 for none; fails
/// the test when a job is in two parts or a part is empty or longer than `chunk`.
std::vector<int> team_pack_owner_of_jobs(const std::vector<colored::Range>& ranges, int batches, int jobs, int threads,
                                         int chunk, std::vector<colored::PackPart>& parts) {
  colored::pack_parts(ranges, batches, threads, chunk, parts);
  std::vector<int> owner(static_cast<size_t>(jobs), -1);
  for (size_t q = 0; q < parts.size(); ++q) {
    EXPECT_LT(parts[q].begin, parts[q].end) << "part " << q;
    EXPECT_LE(parts[q].end - parts[q].begin, chunk) << "part " << q;
    for (int j = parts[q].begin; j < parts[q].end; ++j) {
      EXPECT_EQ(owner[static_cast<size_t>(j)], -1) << "job " << j << " in two parts";
      owner[static_cast<size_t>(j)] = static_cast<int>(q);
    }
  }
  return owner;
}

TEST(PgsColoredTeamPack, PartsHandOutEachJobOnceInMemberBlocksOfEveryRange) {
  // Singles [0, 37) in three colours and an overflow range, pairs [0, 9) in two colours.
  const std::vector<colored::Range> ranges = {{0, 20, false, false}, {0, 5, false, true}, {20, 23, false, false},
                                              {5, 9, false, true},   {23, 34, false, false}, {34, 37, true, false}};
  const int batches = 37, jobs = 37 + 9;
  for (int threads = 1; threads <= 4; ++threads)
    for (int chunk : {1, 3, 16}) {
      std::vector<colored::PackPart> parts;
      const std::vector<int> owner = team_pack_owner_of_jobs(ranges, batches, jobs, threads, chunk, parts);
      for (int j = 0; j < jobs; ++j) EXPECT_GE(owner[static_cast<size_t>(j)], 0) << "job " << j << " in no part";
      // Member t's block of each range (single jobs from 0, pair jobs from `batches`) lies in
      // member t's run of parts, and the runs follow each other in member order.
      int last_part = -1;
      for (int t = 0; t < threads; ++t)
        for (const colored::Range& rg : ranges) {
          const int n = rg.end - rg.begin, off = rg.pairs ? batches : 0;
          for (int b = rg.begin + n * t / threads; b < rg.begin + n * (t + 1) / threads; ++b) {
            const int q = owner[static_cast<size_t>(off + b)];
            EXPECT_GE(q, last_part) << threads << " threads, chunk " << chunk << ", job " << off + b;
            last_part = q;
          }
        }
    }
}

/// Fills every byte of `v` with 0xA5. An empty vector's data() may be null, which memset must not
/// be given even for zero bytes (UndefinedBehaviorSanitizer stops on it), so it is skipped.
template <class T>
void team_pack_poison(std::vector<T>& v) {
  if (!v.empty()) std::memset(static_cast<void*>(v.data()), 0xA5, v.size() * sizeof(T));
}

/// A packed problem: the laid-out Prepared after pack_batches, and its permuted λ⁰.
struct TeamPacked {
  colored::Prepared prep;
  std::vector<double> lp, other;
};

/// pack_batches of `laid` on `threads` threads, every output first filled with the same bytes
/// (so a batch, row or λ⁰ slot the pack skipped shows as a difference).
TeamPacked team_pack_on(const LcpProblem& p, const Eigen::VectorXd& l0, const colored::Prepared& laid, int threads,
                        bool compact, double omega, int stage_from) {
  TeamPacked f{laid, std::vector<double>(laid.row_of.size(), -7.0), std::vector<double>(laid.row_of.size(), -7.0)};
  colored::Prepared& q = f.prep;
  if (compact) q.compact.resize(q.batches.size());
  team_pack_poison(q.batches);
  team_pack_poison(q.compact);
  team_pack_poison(q.pairs);
  std::fill(q.row_of.begin(), q.row_of.end(), -9);
  std::fill(q.diag.begin(), q.diag.end(), -9.0);
  std::atomic<int> side_runs{0};
  auto side = [&](int) { ++side_runs; };
  const PartJob side_job(side);
  colored::pack_batches(p, l0, omega, compact, q, f.lp.data(), f.other.data(), threads, &side_job, stage_from);
  EXPECT_EQ(side_runs.load(), 1);
  return f;
}

void expect_team_packs_equal(const TeamPacked& a, const TeamPacked& b, const std::string& at) {
  EXPECT_EQ(a.prep.compact_on, b.prep.compact_on) << at;
  EXPECT_EQ(a.prep.staged_now, b.prep.staged_now) << at;
  EXPECT_TRUE(test::bytes_equal(a.prep.batches, b.prep.batches)) << at << ": batches";
  EXPECT_TRUE(test::bytes_equal(a.prep.compact, b.prep.compact)) << at << ": compact batches";
  EXPECT_TRUE(test::bytes_equal(a.prep.pairs, b.prep.pairs)) << at << ": pair batches";
  EXPECT_TRUE(test::bytes_equal(a.prep.diag, b.prep.diag)) << at << ": A_ii";
  EXPECT_TRUE(test::bytes_equal(a.lp, b.lp)) << at << ": λ⁰";
  EXPECT_TRUE(test::bytes_equal(a.other, b.other)) << at << ": λ⁰ (second buffer)";
  EXPECT_EQ(a.prep.row_of, b.prep.row_of) << at;
  EXPECT_EQ(a.prep.failed, b.prep.failed) << at;
}

TEST(PgsColoredTeamPack, PackedProblemIsTheSameBytesOnOneTwoAndThreeThreads) {
  test::TestRng rng(11);
  const std::pair<const char*, LcpProblem> problems[] = {
      {"pile", test::settled_problem(stress::scaled_seed_pile(400), 100)},
      {"mass ratio (manifolds)", test::settled_problem(stress::pyramid_mass_ratio(10.0, true), 30)},
      {"random, every fourth frictionless", test::random_contact(300, 2000, true, rng, 0.5, 4)}};
  for (const auto& [what, p] : problems) {
    const Eigen::VectorXd l0 = test::mixed_sign_start(p);
    for (const bool local : {false, true}) {
      ContactColorer colorer;
      colored::Prepared laid;
      ASSERT_EQ(colored::layout(p, colorer, nullptr, 1, laid, nullptr, local), "") << what;
      ASSERT_GT(laid.ranges.size(), 2u) << what;
      for (const bool compact : {false, true})
        for (const int stage_from : {0, 1 << 30})
          for (const double omega : {1.0, 1.5}) {
            const std::string at = std::string(what) + (local ? ", locality" : "") + (compact ? ", compact" : "") +
                                   (stage_from == 0 ? ", staged" : ", gathered") + ", ω " + std::to_string(omega);
            const TeamPacked one = team_pack_on(p, l0, laid, 1, compact, omega, stage_from);
            EXPECT_EQ(one.prep.staged_now, stage_from == 0 && colored::simd_pack_available()) << at;
            for (const int threads : {2, 3})
              expect_team_packs_equal(one, team_pack_on(p, l0, laid, threads, compact, omega, stage_from),
                                      at + ", " + std::to_string(threads) + " threads");
          }
    }
  }
}

}  // namespace
}  // namespace dc
