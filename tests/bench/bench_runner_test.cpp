// The bench's relationships on a small settling scene: the oracle copy converges at once,
// the ordering copy < builtin < zero holds, paired mode evaluates identical steps for every
// starter, and the report files hold what docs/bench.md promises.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench_report.hpp"
#include "bench_runner.hpp"
#include "cli_helpers.hpp"
#include "dc/engine/error.hpp"
#include "dc/io/h5.hpp"

namespace dc {
namespace {

bench::BenchOptions small_pile() {
  bench::BenchOptions o;
  o.scene.bodies.count = 24;
  o.scene.bodies.mean = {15.0, 5.0};
  o.scene.bodies.sigma = 3.0;
  o.scene.time.steps = 160;
  o.sweeps = 600;
  o.seeds = {3};
  o.warmstarts = {"zero", "builtin", "copy", "sph", "sph-prev"};
  return o;
}

const bench::StarterSummary& get(const std::vector<bench::StarterSummary>& s, const std::string& n) {
  for (const auto& x : s)
    if (x.name == n) return x;
  throw std::runtime_error("no starter " + n);
}

TEST(BenchRunner, PairedOrderingOnASettlingPile) {
  const auto r = bench::run_bench(small_pile(), default_warm_starters());
  ASSERT_EQ(r.starters.size(), 5u);
  const std::size_t steps = r.starters[0].sweeps_to_tol.size();
  ASSERT_GT(steps, 100u);
  for (const auto& rec : r.starters) {
    EXPECT_EQ(rec.sweeps_to_tol.size(), steps);
    EXPECT_EQ(rec.step, r.starters[0].step) << "paired: identical steps";
    EXPECT_EQ(rec.theta.size(), steps * 600);
    EXPECT_EQ(rec.residual.size(), steps * r.budgets.size());
  }
  const auto s = bench::summarise(r);
  EXPECT_LE(get(s, "copy").median_sweeps_to_tol, 2);
  EXPECT_LT(get(s, "copy").median_sweeps_to_tol, get(s, "builtin").median_sweeps_to_tol);
  EXPECT_LT(get(s, "builtin").median_sweeps_to_tol, get(s, "zero").median_sweeps_to_tol);
  EXPECT_LT(get(s, "sph").median_sweeps_to_tol, get(s, "builtin").median_sweeps_to_tol);
  // sph-prev smooths the previous step's λ through the grid (no oracle): at the first contact
  // step it has nothing to smooth (the zero guess), afterwards a guess of its own, far from
  // the oracle quality of sph.
  const auto& zero_rec = r.starters[0];
  const auto& prev_rec = r.starters[4];
  ASSERT_EQ(prev_rec.name, "sph-prev");
  EXPECT_FALSE(prev_rec.uses_oracle);
  EXPECT_EQ(prev_rec.sweeps_to_tol[0], zero_rec.sweeps_to_tol[0]);
  EXPECT_EQ(prev_rec.initial_error[0], zero_rec.initial_error[0]);
  EXPECT_NE(prev_rec.initial_error, zero_rec.initial_error);
  EXPECT_GT(get(s, "sph-prev").median_sweeps_to_tol, 5 * get(s, "sph").median_sweeps_to_tol);
  EXPECT_GT(get(s, "sph-prev").initial_error, 1e3 * get(s, "sph").initial_error);
  // The trade: more sweeps never leave a (much) larger residual for the same starter.
  const auto& z = r.starters[0];
  const std::size_t B = r.budgets.size();
  double first = 0, last = 0;
  for (std::size_t i = 0; i < steps; ++i) {
    first += z.residual[i * B];
    last += z.residual[i * B + B - 1];
  }
  EXPECT_LT(last, first);
}

// copy-noise:R: R = 0 is the copy, and more relative noise costs more sweeps.
TEST(BenchRunner, CopyNoiseCostsSweepsMonotonicallyInTheNoise) {
  auto o = small_pile();
  o.warmstarts = {"copy", "copy-noise:0", "copy-noise:0.001", "copy-noise:0.3"};
  const auto r = bench::run_bench(o, default_warm_starters());
  EXPECT_EQ(r.starters[0].sweeps_to_tol, r.starters[1].sweeps_to_tol);
  const auto s = bench::summarise(r);
  EXPECT_LE(get(s, "copy").median_sweeps_to_tol, get(s, "copy-noise:0.001").median_sweeps_to_tol);
  EXPECT_LT(get(s, "copy-noise:0.001").median_sweeps_to_tol, get(s, "copy-noise:0.3").median_sweeps_to_tol);
  for (const char* bad : {"copy-noise", "copy-noise:-1", "copy-noise:x", "copy-noise:0.1x"})
    EXPECT_THROW((void)default_warm_starters().make(bad), ConfigError) << bad;
}

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
  o.warmstarts = {"copy:x"};
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

TEST(BenchReport, WritesSummaryResultsAndReport) {
  auto o = small_pile();
  o.scene.time.steps = 90;
  o.warmstarts = {"zero", "builtin", "copy:2"};
  const auto r = bench::run_bench(o, default_warm_starters());
  test::TempDir dir;
  const auto files = bench::write_report(r, dir.path().string());
  std::ifstream js(dir.file("summary.json"));
  std::stringstream ss;
  ss << js.rdbuf();
  const std::string j = ss.str();
  for (const char* key : {"\"warmstarters\"", "\"zero\"", "\"copy:2\"", "\"median_sweeps_to_tol\"",
                          "\"unconverged_share\"", "\"warmstart_ms\"", "\"solve_ms\"", "\"total_ms\"", "\"scene\"",
                          "\"seeds\"", "\"git\"", "\"build\""})
    EXPECT_NE(j.find(key), std::string::npos) << key;
  const H5File f = H5File::open_read(dir.file("results.h5"));
  const hsize_t n = r.starters[0].sweeps_to_tol.size();
  f.require_shape("/warmstarters/builtin/theta", {n, 600});
  f.require_shape("/warmstarters/copy:2/residual", {n, r.budgets.size()});
  EXPECT_EQ(f.read_strings("/warmstarter_names"), (std::vector<std::string>{"zero", "builtin", "copy:2"}));
  EXPECT_EQ(f.read_strings("/warmstarter_groups"), (std::vector<std::string>{"zero", "builtin", "copy:2"}));
  EXPECT_EQ(f.attribute_string("/warmstarters/copy:2", "name"), "copy:2");
  EXPECT_TRUE(std::filesystem::exists(dir.file("report.md")));
  f.require_shape("/statistics/median_sweeps_to_tol", {3, 3});
  f.require_shape("/statistics/ratio_median_sweeps_to_tol", {4, 3});  // copy:2, builtin / zero; zero, copy:2 / builtin
  for (const char* png : {"intervals.png", "convergence.png", "sweeps_per_step.png", "time_breakdown.png", "pareto.png"})
    EXPECT_TRUE(std::filesystem::exists(dir.file(png))) << png << " (python3-matplotlib/h5py installed?)";
}

}  // namespace
}  // namespace dc
