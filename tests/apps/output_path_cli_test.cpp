// Every command checks its output paths before any work (docs/robustness.md "Outputs checked
// before the work"): a missing parent, a directory where a file is expected or an unwritable
// place is a one-line error and exit 1 before a scene is simulated, a data set read or a
// bench run — the commands' own output (a table, "Simulated …") never appears. And `bench
// --out DIR` replaces an earlier DIR only with a complete report of the new run.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "apps/cli_helpers.hpp"

namespace dc {
namespace {

/// The command failed at the door: exit 1, one line on stderr naming `path`, nothing on stdout.
void expect_refused_before_work(const test::CliResult& r, const std::string& path) {
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(path), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "") << "the command did its work before checking the output path";
}

const std::string kSmallScene = "--set bodies.count=20 --set bodies.mean=[15.0,4.0] --set bodies.sigma=3.0 ";

TEST(OutputPathCli, SimulateRefusesEveryBadOutBeforeSimulating) {
  test::TempDir dir;
  const std::string missing = dir.file("no/such/dir/run.h5");
  expect_refused_before_work(test::run_cli("simulate " + kSmallScene + "--steps 400 --out " + missing), missing);
  // A directory where the trajectory file should go.
  expect_refused_before_work(test::run_cli("simulate " + kSmallScene + "--steps 400 --out " + dir.path().string()),
                             dir.path().string());
  // A parent nobody can create files in — root included (/proc).
  expect_refused_before_work(test::run_cli("simulate " + kSmallScene + "--steps 400 --out /proc/run.h5"),
                             "/proc/run.h5");
  // A parent that is a file.
  const std::string file = dir.file("plain");
  std::ofstream(file) << "x";
  expect_refused_before_work(test::run_cli("simulate " + kSmallScene + "--steps 400 --out " + file + "/run.h5"),
                             file + "/run.h5");
}

TEST(OutputPathCli, EveryCommandChecksItsOutputFirst) {
  test::TempDir dir;
  const std::string bad = dir.file("missing/out");
  // train reads the data set only after its --out was checked (the data set does not exist).
  expect_refused_before_work(test::run_cli("train --data " + dir.file("nope.h5") + " --out " + bad + ".h5"),
                             bad + ".h5");
  expect_refused_before_work(test::run_cli("generate --sims 2 --steps 20 --out " + bad + ".h5"), bad + ".h5");
  expect_refused_before_work(test::run_cli("bench --quick --steps 30 --out " + bad), bad);
  expect_refused_before_work(test::run_cli("render " + dir.file("nope.h5") + " --out " + bad + ".gif"), bad + ".gif");
  expect_refused_before_work(test::run_cli("lcp convert " + dir.file("nope.dat") + " " + bad + ".dat"), bad + ".dat");
  expect_refused_before_work(test::run_cli("pgs-landscape --data " + dir.file("nope.h5") + " --out " + bad + ".csv"),
                             bad + ".csv");
  expect_refused_before_work(test::run_cli("sph-study --steps 20 --out " + bad), bad);
  expect_refused_before_work(test::run_cli("stress --quick --out " + bad), bad);
  // bench --out names a directory: an existing plain file there is refused before the bench.
  const std::string file = dir.file("summary");
  std::ofstream(file) << "x";
  expect_refused_before_work(test::run_cli("bench --quick --steps 30 --out " + file), file);
}

std::string small_bench(const std::string& seeds, const std::string& out) {
  return "bench --scene " + std::string(DC_SOURCE_DIR) + "/scenes/small.toml --steps 40 --seeds " + seeds +
         " --mode rollout --warmstarts zero,builtin --out " + out;
}

TEST(OutputPathCli, BenchReplacesAnEarlierReportOnlyWithACompleteNewOne) {
  test::TempDir dir;
  const std::string out = dir.file("report");
  ASSERT_EQ(test::run_cli(small_bench("1..2", out)).exit_code, 0);
  const std::string first = test::slurp(out + "/summary.json");
  ASSERT_NE(first.find("\"seeds\": [1, 2]"), std::string::npos) << first;

  // A file the bench did not write blocks the directory: refused before the run, naming it.
  std::ofstream(out + "/stale.txt") << "left by the user";
  const auto refused = test::run_cli(small_bench("3..3", out));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("stale.txt"), std::string::npos) << refused.err;
  EXPECT_EQ(test::slurp(out + "/stale.txt"), "left by the user");
  EXPECT_EQ(test::slurp(out + "/summary.json"), first);
  std::filesystem::remove(out + "/stale.txt");

  // A run that fails before its report exists (its scene is refused after the check of --out
  // passed) leaves the earlier report as it was.
  EXPECT_EQ(test::run_cli(small_bench("3..3", out) + " --set time.dt=-1").exit_code, 1);
  EXPECT_EQ(test::slurp(out + "/summary.json"), first);

  // A complete new run replaces the earlier report: nothing of the earlier one is left (a
  // file of an earlier size sweep, which this run does not write, goes too).
  std::ofstream(out + "/scale.md") << "an earlier size sweep";
  const auto r = test::run_cli(small_bench("3..3", out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::slurp(out + "/summary.json").find("\"seeds\": [3]"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(out + "/scale.md"));
  EXPECT_TRUE(std::filesystem::exists(out + "/report.md"));
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))  // no staging or old directories left
    EXPECT_EQ(e.path().filename(), "report") << e.path();
  for (const auto& e : std::filesystem::directory_iterator(out))
    EXPECT_NE(e.path().filename().string().rfind("partial-run-", 0), 0u) << e.path();
}

}  // namespace
}  // namespace dc

namespace dc {
namespace {

/// Refused at the door because of the output's name: exit 1, one line naming the file and
/// the extensions expected, nothing written.
void expect_wrong_extension(const test::CliResult& r, const std::string& path, const std::string& expected) {
  expect_refused_before_work(r, path);
  EXPECT_NE(r.err.find("expected a name ending in " + expected), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(OutputPathCli, AnOutputNamedForAnotherFormatIsRefused) {
  test::TempDir dir;
  const std::string data = std::string(DC_SOURCE_DIR) + "/tests/data/";
  expect_wrong_extension(test::run_cli("simulate " + kSmallScene + "--steps 400 --out " + dir.file("run.txt")),
                         dir.file("run.txt"), ".h5 or .hdf5");
  expect_wrong_extension(test::run_cli("generate --sims 2 --steps 20 --out " + dir.file("d.txt")), dir.file("d.txt"),
                         ".h5 or .hdf5");
  expect_wrong_extension(test::run_cli("train --data " + dir.file("nope.h5") + " --out " + dir.file("m.txt")),
                         dir.file("m.txt"), ".h5 or .hdf5");
  expect_wrong_extension(test::run_cli("pgs-landscape --data " + dir.file("nope.h5") + " --out " + dir.file("l.txt")),
                         dir.file("l.txt"), ".csv");
  expect_wrong_extension(test::run_cli("lcp convert " + data + "lcp/small_spd.dat " + dir.file("p.txt")),
                         dir.file("p.txt"), ".dat");
  expect_wrong_extension(test::run_cli("lcp convert " + data + "lcp/small_spd.dat " + dir.file("p.dat") + " --format fclib"),
                         dir.file("p.dat"), ".h5 or .hdf5");
  // The names that fit are taken (.h5 is FCLIB, like .hdf5; the case of the extension is free).
  EXPECT_EQ(test::run_cli("lcp convert " + data + "fc2d/FrictionContactProblem00394.dat " + dir.file("p.h5")).exit_code, 0);
  EXPECT_EQ(test::run_cli("simulate " + kSmallScene + "--steps 2 --out " + dir.file("run.HDF5")).exit_code, 0);
}

}  // namespace
}  // namespace dc
