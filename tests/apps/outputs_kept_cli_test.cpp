// No command deletes or replaces what it did not write, and faults end in one line
// (docs/robustness.md, "Outputs and faults"): bench --out DIR refuses a directory holding
// files of others and writes into an earlier bench output or "."; an interrupted simulate
// keeps the earlier OUT byte for byte; .dat outputs are written to a temporary and renamed;
// a bad --export-problems folder is refused before the run; a file-size limit (ulimit -f)
// ends in one line and exit 1, not a signal.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <filesystem>
#include <string>

#include "cli_helpers.hpp"
#include "dc/io/h5.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

/// A tiny scene: 12 circles in a 12 × 12 box.
const std::string kScene =
    " --set world.width=12 --set world.height=12 --set bodies.count=12 --set bodies.mean=[6.0,6.0]"
    " --set bodies.sigma=2.0";
const std::string kBench = "bench --warmstarts zero --seeds 1 --steps 5 --sweeps 50 --mode rollout" + kScene;
const std::string kData = std::string(DC_SOURCE_DIR) + "/tests/data/lcp/";

/// No entry of `dir` is a bench's partial-run folder or a temporary.
void expect_no_leftovers(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    EXPECT_NE(name.rfind("partial-run-", 0), 0u) << "left behind: " << e.path();
    EXPECT_NE(e.path().extension(), ".tmp") << "left behind: " << e.path();
  }
}

TEST(OutputsKeptCli, BenchRefusesADirectoryHoldingOtherFilesBeforeTheRun) {
  const test::TempDir dir;
  fs::create_directories(dir / "d/mydata");
  const std::string thesis = dir / "d/mydata/thesis.tex";
  std::ofstream(thesis) << "x\n";
  const auto r = test::run_cli(kBench + " --out " + (dir / "d"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("mydata"), std::string::npos) << r.err;  // the entry in the way
  EXPECT_EQ(r.out, "") << "the bench ran before the refusal";
  EXPECT_EQ(test::slurp_file(thesis), "x\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "d"), fs::directory_iterator{}), 1);
}

TEST(OutputsKeptCli, BenchReplacesItsOwnEarlierOutputAndWritesIntoDot) {
  const test::TempDir dir;
  const std::string out = dir / "d";
  ASSERT_EQ(test::run_cli(kBench + " --out " + out).exit_code, 0);
  ASSERT_TRUE(fs::exists(out + "/report.md"));
  ASSERT_EQ(test::run_cli(kBench + " --out " + out + "/").exit_code, 0);  // an earlier bench output: replaced
  EXPECT_TRUE(fs::exists(out + "/summary.json"));
  expect_no_leftovers(out);
  // --out . in an empty directory and in an earlier output (the lock file lies next to it).
  fs::create_directories(dir / "here");
  const std::string cd = "cd " + (dir / "here") + " && ";
  for (int run = 0; run < 2; ++run) {
    const int rc = std::system((cd + DC_CLI + " " + kBench + " --out . >/dev/null 2>&1").c_str());
    EXPECT_EQ(rc, 0) << "run " << run;
    EXPECT_TRUE(fs::exists(dir / "here/report.md")) << "run " << run;
    expect_no_leftovers(dir / "here");
  }
}

TEST(OutputsKeptCli, BenchDirectoryFollowsTheUmask) {
  const test::TempDir dir;
  const std::string out = dir / "d";
  const int rc = std::system(("umask 022 && " + std::string(DC_CLI) + " " + kBench + " --out " + out + " >/dev/null 2>&1").c_str());
  ASSERT_EQ(rc, 0);
  struct stat st {};
  ASSERT_EQ(::stat(out.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0755u);
}

// SIGINT (Ctrl-C) of a long simulate: the earlier complete OUT is byte for byte as it was, the
// steps done are in OUT-STEM.interrupted.h5, exit 130 with one line.
TEST(OutputsKeptCli, InterruptedSimulateKeepsTheEarlierTrajectory) {
  const test::TempDir dir;
  const std::string out = dir / "keep.h5", err = dir / "err.txt";
  ASSERT_EQ(test::run_cli("simulate --steps 20" + kScene + " --out " + out).exit_code, 0);
  const std::string before = test::slurp_file(out);
  const pid_t pid = test::spawn_cli("simulate --steps 1000000" + kScene + " --out " + out, err, test::ChildLog::StderrOnly);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(test::wait_for_file(out + ".tmp", pid));
  ::usleep(300000);
  ::kill(pid, SIGINT);
  EXPECT_EQ(test::wait_exit(pid), 130);
  const std::string log = test::slurp(err);
  EXPECT_EQ(test::count_lines(log), 1) << log;
  EXPECT_NE(log.find("keep.interrupted.h5"), std::string::npos) << log;
  EXPECT_TRUE(test::slurp_file(out) == before) << out << " was changed by the interrupted run";
  const H5File partial = H5File::open_read(dir / "keep.interrupted.h5");
  EXPECT_GT(partial.shape("/solver/sweeps").at(0), 0u);
  expect_no_leftovers(dir.path());
}

// lcp convert writes OUT.tmp and renames it: past a file-size limit the earlier OUT stays.
TEST(OutputsKeptCli, DatOutputOnAFullDiskKeepsTheEarlierFile) {
  const test::TempDir dir;
  const std::string out = dir / "out.dat";
  const std::string args = "lcp convert \"" + kData + "contact_12.dat\" " + out + " --storage 0";
  ASSERT_EQ(test::run_cli(args).exit_code, 0);
  const std::string before = test::slurp_file(out);
  ASSERT_GT(before.size(), 600u);
  const auto r = test::run_cli_with_file_limit(args, 512);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(out), std::string::npos) << r.err;
  EXPECT_TRUE(test::slurp_file(out) == before);
  expect_no_leftovers(dir.path());
}

// ulimit -f as a shell sets it (SIGXFSZ at its default): one line and exit 1, not a signal,
// and the earlier trajectory intact.
TEST(OutputsKeptCli, FileSizeLimitEndsInOneLineNotASignal) {
  const test::TempDir dir;
  const std::string out = dir / "run.h5";
  const std::string args = "simulate --steps 60" + kScene + " --out " + out;
  ASSERT_EQ(test::run_cli(args).exit_code, 0);
  const std::string before = test::slurp_file(out);
  ASSERT_GT(before.size(), 8192u);
  const auto r = test::run_cli_with_file_limit(args, 8192, /*ignore_sigxfsz=*/false);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("deepcontact: error: ", 0), 0u) << r.err;
  EXPECT_TRUE(test::slurp_file(out) == before);
  expect_no_leftovers(dir.path());
}

// generate under ulimit -f as a shell sets it: its shard cannot be written; one line naming
// the shard, exit 1, no signal, and nothing under the final name (the partial run stays
// resumable under OUT.partial and OUT.shards).
TEST(OutputsKeptCli, GenerateUnderAFileSizeLimitEndsInOneLineNamingTheFile) {
  const test::TempDir dir;
  const std::string out = dir / "data.h5";
  const auto r = test::run_cli_with_file_limit(
      "generate --sims 2 --count 10..12 --steps 20 --threads 1" + kScene + " --out " + out, 8192,
      /*ignore_sigxfsz=*/false);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("deepcontact: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("data.h5.shards/"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  expect_no_leftovers(dir.path());
}

/// A stand-in for the renderer's Python (DC_BENCH_PYTHON): writes `bytes` to the path after
/// --out, then exits with `code`.
std::string fake_renderer(const test::TempDir& dir, const std::string& bytes, int code) {
  const std::string path = dir / ("fake-python-" + std::to_string(code));
  std::ofstream(path) << "#!/bin/sh\nwhile [ $# -gt 0 ]; do [ \"$1\" = --out ] && printf '" << bytes
                      << "' > \"$2\"; shift; done\nexit " << code << "\n";
  fs::permissions(path, fs::perms::owner_all);
  return path;
}

// render draws into OUT.tmp.EXT and renames only a complete image onto OUT: a renderer that
// fails after writing part of its output leaves the earlier OUT byte for byte.
TEST(OutputsKeptCli, FailedRenderKeepsTheEarlierImage) {
  const test::TempDir dir;
  const std::string out = dir / "run.gif";
  std::ofstream(out) << "earlier image";
  for (const auto& [code, expected] : {std::pair{1, std::string("earlier image")}, {0, std::string("new image")}}) {
    ::setenv("DC_BENCH_PYTHON", fake_renderer(dir, code ? "partial" : "new image", code).c_str(), 1);
    const auto r = test::run_cli("render " + (dir / "missing.h5") + " --out " + out);
    ::unsetenv("DC_BENCH_PYTHON");
    EXPECT_EQ(r.exit_code, code) << r.err;
    EXPECT_EQ(test::slurp_file(out), expected) << "renderer exit " << code;
    EXPECT_FALSE(fs::exists(out + ".tmp.gif")) << "renderer exit " << code;
  }
}

// An export folder no file can be created in (/proc, also for root) is refused before the
// scene is loaded: one line naming it, no trajectory started.
TEST(OutputsKeptCli, UnwritableExportFolderIsRefusedBeforeTheRun) {
  const test::TempDir dir;
  const std::string out = dir / "run.h5";
  const auto r = test::run_cli("simulate --steps 100000" + kScene + " --out " + out + " --export-problems /proc");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("/proc"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_FALSE(fs::exists(out));
  expect_no_leftovers(dir.path());
}

}  // namespace
}  // namespace dc
