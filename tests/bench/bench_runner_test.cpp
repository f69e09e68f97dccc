// The bench's relationships on a small settling scene: the oracle copy converges at once,
// the ordering copy < builtin < zero holds, paired mode evaluates identical steps for every
// starter, and the report files hold what docs/bench.md promises.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench/bench_fixtures.hpp"
#include "dc/bench/bench_report.hpp"
#include "dc/bench/bench_runner.hpp"
#include "dc/bench/bench_summary.hpp"
#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

using test::capped_pile;
using test::get;
using test::small_pile;



TEST(BenchRunner, RolloutModeRunsEachStarterOnItsOwnTrajectory) {
  auto o = small_pile();
  o.mode = bench::Mode::Rollout;
  o.scene.time.steps = 60;
  o.warmstarts = {"zero", "builtin", "zero"};
  const auto r = bench::run_bench(o, default_warm_starters());
  ASSERT_EQ(r.starters.size(), 3u);
  const auto &zero = r.starters[0], &builtin = r.starters[1], &zero2 = r.starters[2];
  const std::size_t n = zero.sweeps_to_tol.size();
  ASSERT_GT(n, 10u);
  EXPECT_EQ(zero.step, r.step_index);
  // The same starter on the same scene drives the same trajectory, bit for bit.
  EXPECT_EQ(zero2.step, zero.step);
  EXPECT_EQ(zero2.rows, zero.rows);
  EXPECT_EQ(zero2.sweeps_to_tol, zero.sweeps_to_tol);
  EXPECT_EQ(zero2.initial_error, zero.initial_error);
  // builtin has nothing to remember at the first contact step: there it is the zero guess.
  ASSERT_FALSE(builtin.step.empty());
  EXPECT_EQ(builtin.step[0], zero.step[0]);
  EXPECT_EQ(builtin.sweeps_to_tol[0], zero.sweeps_to_tol[0]);
  EXPECT_EQ(builtin.initial_error[0], zero.initial_error[0]);
  // Afterwards it starts closer and needs fewer sweeps.
  const auto s = bench::summarise(r);
  EXPECT_LT(get(s, "builtin").median_sweeps_to_tol, get(s, "zero").median_sweeps_to_tol);
  EXPECT_LT(get(s, "builtin").initial_error, get(s, "zero").initial_error);
  // Rollout is not the paired reference trajectory (advanced with λ*): zero's ‖λ*‖ = its
  // initial error agrees at the first contact step and then drifts apart.
  auto paired = o;
  paired.mode = bench::Mode::Paired;
  paired.warmstarts = {"zero"};
  const auto rp = bench::run_bench(paired, default_warm_starters());
  ASSERT_EQ(rp.starters[0].step[0], zero.step[0]);
  EXPECT_EQ(rp.starters[0].initial_error[0], zero.initial_error[0]);
  EXPECT_NE(rp.starters[0].initial_error, zero.initial_error);
}

TEST(BenchRunner, UnknownStarterAndBadOptionsAreConfigErrors) {
  auto o = small_pile();
  o.warmstarts = {"zero", "nope"};
  EXPECT_THROW(bench::run_bench(o, default_warm_starters()), ConfigError);
  o.warmstarts = {"builtin-active:1"};  // a known starter with a bad argument
  EXPECT_THROW(bench::run_bench(o, default_warm_starters()), ConfigError);
  o.warmstarts = {"zero"};
  o.tolerance = 0;
  EXPECT_THROW(bench::run_bench(o, default_warm_starters()), ConfigError);
}

TEST(BenchRunner, DefaultBudgetsAreSortedAndEndAtTheSweeps) {
  for (int n : {1, 7, 100, 3000}) {
    const auto b = bench::default_budgets(n);
    ASSERT_FALSE(b.empty());
    EXPECT_EQ(b.front(), 1);
    EXPECT_EQ(b.back(), n);
    for (std::size_t i = 1; i < b.size(); ++i) EXPECT_LT(b[i - 1], b[i]);
  }
}

// A starter argument may be a path ("cnn:models/x.h5"): its group must not nest.
TEST(BenchReport, StarterGroupNamesEscapeSlashesAndPercent) {
  EXPECT_EQ(bench::starter_group_name("builtin"), "builtin");
  EXPECT_EQ(bench::starter_group_name("cnn:models/a.h5"), "cnn:models%2Fa.h5");
  EXPECT_EQ(bench::starter_group_name("copy:%/"), "copy:%25%2F");
}

}  // namespace
}  // namespace dc
