// The bench runner with oracle starters (copy, copy-noise, sph): the paired ordering on a settling
// pile, the noise a guess may carry, and the report files.
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
#include "research/research_registry.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

using test::capped_pile;
using test::get;
using test::small_pile;



TEST(BenchRunner, PairedOrderingOnASettlingPile) {
  const auto r = bench::run_bench(small_pile(), test::research_registry());
  ASSERT_EQ(r.starters.size(), 5u);
  const std::size_t steps = r.starters[0].sweeps_to_tol.size();
  ASSERT_GT(steps, 100u);
  for (const auto& rec : r.starters) {
    EXPECT_EQ(rec.sweeps_to_tol.size(), steps);
    EXPECT_EQ(rec.step, r.starters[0].step) << "paired: identical steps";
    EXPECT_EQ(rec.theta.rows(), steps);
    EXPECT_EQ(rec.theta.row_length(), 600u);
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
  const auto r = bench::run_bench(o, test::research_registry());
  EXPECT_EQ(r.starters[0].sweeps_to_tol, r.starters[1].sweeps_to_tol);
  const auto s = bench::summarise(r);
  EXPECT_LE(get(s, "copy").median_sweeps_to_tol, get(s, "copy-noise:0.001").median_sweeps_to_tol);
  EXPECT_LT(get(s, "copy-noise:0.001").median_sweeps_to_tol, get(s, "copy-noise:0.3").median_sweeps_to_tol);
  for (const char* bad : {"copy-noise", "copy-noise:-1", "copy-noise:x", "copy-noise:0.1x"})
    EXPECT_THROW((void)test::research_registry().make(bad), ConfigError) << bad;
}

TEST(BenchReport, WritesSummaryResultsAndReport) {
  auto o = small_pile();
  o.scene.time.steps = 90;
  o.warmstarts = {"zero", "builtin", "copy:2"};
  const auto r = bench::run_bench(o, test::research_registry());
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
  // Per-sweep θ of every step only on request (keep_theta, `--theta`); its quartiles always.
  f.require_shape("/warmstarters/builtin/theta_quartiles", {600, 3});
  EXPECT_FALSE(f.exists("/warmstarters/builtin/theta"));
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

TEST(FamiliesBench, WarmupStepsAreNotEvaluatedAndNoOracleRefusesOracleStarters) {
  bench::BenchOptions o = capped_pile();
  o.max_sweeps = 0;
  o.warmup_steps = 100;
  o.oracle = false;
  const auto r = bench::run_bench(o, test::research_registry());
  for (const auto& rec : r.starters) {
    ASSERT_FALSE(rec.step.empty());
    EXPECT_GE(rec.step.front(), 100);
    EXPECT_LE(rec.step.size(), 20u);
  }
  o.warmstarts = {"zero", "copy"};
  EXPECT_THROW(bench::run_bench(o, test::research_registry()), ConfigError);
}

}  // namespace
}  // namespace dc
