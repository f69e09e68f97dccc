// Full disk (docs/robustness.md, finding 6): every command that writes an --out file, run
// with a file-size limit
// (setrlimit(RLIMIT_FSIZE), SIGXFSZ ignored, so writes fail with EFBIG as on a full disk),
// exits non-zero with one line on stderr, leaves the complete files an earlier run wrote
// under the final names bit-for-bit intact, and leaves no temporary file behind.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_helpers.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

/// Small enough that none of the outputs below fits, large enough for the error message.
constexpr std::size_t kLimitBytes = 8192;

/// A tiny scene: 12 circles in a 12 × 12 box.
const std::string kScene =
    " --set world.width=12 --set world.height=12 --set bodies.count=12 --set bodies.mean=[6.0,6.0]"
    " --set bodies.sigma=2.0";

/// Runs `args` without a limit, then `args + again` with the limit; `outputs` are the files
/// the first run completes (the first must be larger than the limit), `dir` the directory
/// that must hold no "*.tmp" afterwards.
void expect_full_disk_is_clean(const std::string& args, const std::string& again,
                               const std::vector<std::string>& outputs, const fs::path& dir) {
  const auto first = test::run_cli(args);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  std::vector<std::string> before;
  for (const auto& f : outputs) before.push_back(test::slurp_file(f));
  ASSERT_GT(before.front().size(), kLimitBytes) << outputs.front() << " must not fit under the limit";

  const auto failed = test::run_cli_with_file_limit(args + again, kLimitBytes);
  EXPECT_EQ(failed.exit_code, 1) << args;
  EXPECT_EQ(failed.err.rfind("deepcontact: error: ", 0), 0u) << failed.err;
  EXPECT_EQ(test::count_lines(failed.err), 1) << failed.err;
  for (std::size_t i = 0; i < outputs.size(); ++i)
    EXPECT_TRUE(test::slurp_file(outputs[i]) == before[i]) << outputs[i] << " was changed by the failed run";
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_NE(entry.path().extension(), ".tmp") << "temporary file left behind: " << entry.path();
}

// The trajectory is streamed to OUT.tmp on disk (memory independent of the step count): the
// failed write is seen where it happens, the file is abandoned and closed, and the process
// exits with its one line and status 1 (docs/robustness.md "Outputs and faults").
TEST(FullDiskCli, SimulateKeepsTheEarlierTrajectory) {
  const test::TempDir dir;
  const std::string out = dir / "run.h5";
  expect_full_disk_is_clean("simulate" + kScene + " --steps 60 --out " + out, "", {out}, dir.path());
}

// The failed run keeps its OUT.partial (what --resume continues); OUT itself must stay the
// earlier complete data set even though the second run was told to replace it (--force).
// Each shard is built in memory and written atomically, so the failure is one line naming
// the shard and exit 1.
TEST(FullDiskCli, GenerateKeepsTheEarlierDataSet) {
  const test::TempDir dir;
  const std::string out = dir / "data.h5";
  expect_full_disk_is_clean("generate --sims 2 --count 10..12 --steps 20 --threads 1" + kScene + " --out " + out,
                            " --force", {out}, dir.path());
}

// A real full filesystem (ENOSPC): a small tmpfs mounted in a private mount namespace
// (`unshare --user --map-root-user --mount`, no privileges needed where user namespaces are
// enabled; skipped elsewhere). Here the data-set writer abandons the failed file (its
// descriptor moved to a memfd) and the process exits with its one-line error and status 1.
TEST(FullDiskCli, GenerateOnAFullFilesystemExitsWithOneLine) {
  const test::TempDir dir;
  const std::string earlier = dir / "earlier.h5";
  const std::string args = "generate --sims 2 --count 10..12 --steps 20 --threads 1" + kScene;
  const auto first = test::run_cli(args + " --out " + earlier);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto size = fs::file_size(earlier);
  // Room for the earlier file and half of another: the new OUT.partial cannot complete.
  const std::string mnt = dir / "mnt", out = mnt + "/data.h5", status = dir / "status", err = dir / "err";
  fs::create_directories(mnt);
  const std::string script = "mount -t tmpfs -o size=" + std::to_string(size + size / 2 + 8192) + " tmpfs " + mnt +
                             " || exit 0; cp " + earlier + " " + out + " && " + DC_CLI + " " + args +
                             " --force --out " + out + " >/dev/null 2>" + err + "; echo $? > " + status +
                             "; cmp -s " + earlier + " " + out + " && echo intact >> " + status + "; ls -a " + mnt +
                             " >> " + status;
  const int rc = std::system(("unshare --user --map-root-user --mount sh -c '" + script + "' 2>/dev/null").c_str());
  if (rc != 0 || !fs::exists(status)) GTEST_SKIP() << "cannot mount a tmpfs in a user namespace here";
  const std::string report = test::slurp_file(status);
  EXPECT_EQ(report.rfind("1\nintact\n", 0), 0u) << report;
  EXPECT_EQ(report.find(".tmp"), std::string::npos) << report;
  // The error is the first line. libhdf5 1.10.8 may add its own "infinite loop closing
  // library" at exit: the failed write leaks a block inside the library (no id of ours is
  // open; see Hdf5OpenObjects.* and docs/robustness.md), so the line count is not asserted.
  const std::string message = test::slurp_file(err);
  EXPECT_EQ(message.rfind("deepcontact: error: ", 0), 0u) << message;
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
}

TEST(FullDiskCli, BenchKeepsTheEarlierResults) {
  const test::TempDir dir;
  const std::string out = dir / "results";
  expect_full_disk_is_clean("bench --warmstarts zero,builtin --seeds 1 --steps 5 --sweeps 50" + kScene + " --out " + out,
                            "", {out + "/results.h5", out + "/summary.json"}, out);
}

}  // namespace
}  // namespace dc
