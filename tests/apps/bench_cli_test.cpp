// `deepcontact bench --out` end to end: rollout mode gets the same complete report as paired
// mode (every plot, the uncertainty section), and a report that cannot be completed (here: a
// Python that fails) makes the bench exit non-zero with one line naming what is missing.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "apps/cli_helpers.hpp"

namespace dc {
namespace {

const char* const kPlots[] = {"intervals.png", "convergence.png", "sweeps_per_step.png", "time_breakdown.png",
                              "pareto.png"};

std::string small_bench(const std::string& mode, const test::TempDir& dir) {
  return "bench --scene " + std::string(DC_SOURCE_DIR) + "/scenes/small.toml --steps 60 --seeds 1..2 --mode " + mode +
         " --warmstarts zero,builtin --out " + dir.path().string();
}

/// Sets an environment variable for the lifetime of the object (children inherit it).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) { ::setenv(name, value.c_str(), 1); }
  ~ScopedEnv() { ::unsetenv(name_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
};

TEST(BenchCli, RolloutModeWritesTheCompleteReport) {
  for (const std::string mode : {"rollout", "paired"}) {
    test::TempDir dir;
    const auto r = test::run_cli(small_bench(mode, dir));
    ASSERT_EQ(r.exit_code, 0) << mode << ": " << r.err;
    EXPECT_EQ(r.err.find("Traceback"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    const std::string md = test::slurp(dir.file("report.md"));
    EXPECT_NE(md.find("Mode **" + mode + "**"), std::string::npos);
    EXPECT_NE(md.find("## Uncertainty"), std::string::npos);
    EXPECT_NE(md.find(mode == "paired" ? "paired bootstrap" : "resampled independently"), std::string::npos);
    EXPECT_EQ(md.find("missing"), std::string::npos) << md;
    for (const char* png : kPlots) {
      EXPECT_TRUE(std::filesystem::exists(dir.file(png))) << mode << ": " << png << "\n" << test::slurp(dir.file("plots.log"));
      EXPECT_NE(md.find(std::string("](") + png + ")"), std::string::npos) << mode << ": " << png;
    }
    // The frame is rendered in the staging folder, which is gone when the report is complete:
    // render.log names the report's own file, not that folder.
    if (std::filesystem::exists(dir.file("render.log"))) {
      const std::string log = test::slurp(dir.file("render.log"));
      EXPECT_NE(log.find("render: reference_frame.png"), std::string::npos) << log;
      EXPECT_EQ(log.find("partial-run"), std::string::npos) << log;
    }
    const std::string js = test::slurp(dir.file("summary.json"));
    EXPECT_NE(js.find("\"statistics\""), std::string::npos);
    EXPECT_NE(js.find(mode == "paired" ? "\"paired\": true" : "\"paired\": false"), std::string::npos);
  }
}

TEST(BenchCli, AShortWindowAfterAWarmUpGetsEveryPlot) {
  // Two steps of one seed after 120 warm-up steps: the per-step plot once laid its seed labels at step 0,
  // which stretched the figure past what matplotlib can draw.
  test::TempDir dir;
  const auto r = test::run_cli("bench --scene " + std::string(DC_SOURCE_DIR) +
                               "/scenes/small.toml --warmup-steps 120 --steps 122 --seeds 1..1 --warmstarts zero,builtin --out " +
                               dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* png : kPlots)
    EXPECT_TRUE(std::filesystem::exists(dir.file(png))) << png << "\n" << test::slurp(dir.file("plots.log"));
}

TEST(BenchCli, AnIncompleteReportExitsNonZeroWithOneLineNamingTheMissingPlots) {
  test::TempDir dir;
  const ScopedEnv python("DC_BENCH_PYTHON", "/bin/false");
  const auto r = test::run_cli(small_bench("rollout", dir));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("incomplete"), std::string::npos) << r.err;
  for (const char* png : kPlots) EXPECT_NE(r.err.find(png), std::string::npos) << png << ": " << r.err;
  // What could be written is there, and report.md says what is missing.
  EXPECT_TRUE(std::filesystem::exists(dir.file("results.h5")));
  const std::string md = test::slurp(dir.file("report.md"));
  EXPECT_NE(md.find("pareto.png missing"), std::string::npos) << md;
}

// Without contacts there is nothing to plot: every plot says why, and the report is complete.
TEST(BenchCli, PlotsThatDoNotApplySaySoInTheReport) {
  test::TempDir dir;
  const auto r = test::run_cli("bench --scene " + std::string(DC_SOURCE_DIR) +
                               "/scenes/small.toml --set bodies.count=0 --steps 10 --seeds 1..1 --mode rollout "
                               "--warmstarts zero,builtin --out " + dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = test::slurp(dir.file("report.md"));
  for (const char* png : kPlots)
    EXPECT_NE(md.find(std::string(png) + " does not apply to this run: no evaluated steps"), std::string::npos)
        << png << "\n" << md;
}

TEST(BenchCli, SigtermStopsEveryThreadWritesNothingAndExits143) {
  test::TempDir dir;
  const std::filesystem::path out = dir.path() / "earlier";
  std::filesystem::create_directories(out);
  std::ofstream(out / "report.md") << "an earlier run\n";
  const std::string err = (dir.path() / "err.txt").string();
  // Long enough never to finish first: 4 seeds of the seed scene on two threads.
  const pid_t pid = test::spawn_cli("bench --warmstarts zero,builtin --seeds 1..4 --jobs 2 --out " + out.string(), err,
                                    test::ChildLog::StderrOnly);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(test::wait_for(err, "bench: ", pid)) << test::slurp(err);  // the first heartbeat: running
  ::kill(pid, SIGTERM);
  ASSERT_EQ(test::wait_exit(pid), 143) << test::slurp(err);
  const std::string log = test::slurp(err);
  const std::size_t at = log.find("deepcontact: bench interrupted by SIGTERM after ");
  ASSERT_NE(at, std::string::npos) << log;
  EXPECT_EQ(log.find('\n', at), log.size() - 1) << log;  // one line, the last
  EXPECT_NE(log.find("nothing written"), std::string::npos) << log;
  // The earlier DIR is untouched and no staging directory is left next to it.
  EXPECT_EQ(test::slurp((out / "report.md").string()), "an earlier run\n");
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 2u);  // earlier/ and err.txt
}

}  // namespace
}  // namespace dc
