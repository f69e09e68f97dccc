// deepcontact generate as a process: thread-count independence, kill -9 + --resume and
// SIGINT + --resume give the same datasets as an uninterrupted run, and bad inputs fail with
// a one-line error.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "cli_helpers.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/io/h5.hpp"
#include "h5_compare.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;
using test::ChildLog;
using test::slurp;
using test::spawn_cli;
using test::wait_exit;
using test::wait_for;

/// A tiny family (10–14 circles in a 12 × 12 box): 60 steps take ≈ 0.05 s per simulation,
/// kSlow's 250 steps ≈ 0.25 s — long enough to be killed reliably between simulations.
const std::string kScene =
    " --set world.width=12 --set world.height=12 --set bodies.mean=[6.0,6.0] --set bodies.sigma=2.0 --seed 5";
const std::string kFamily = kScene + " --count 10..14 --steps 60";
const std::string kSlow = kScene + " --count 10..14 --steps 250";

using test::TempDir;
using Dir = TempDir;

using Result = test::CliResult;


std::string attribute_text(const H5File& f, const std::string& name) {
  try {
    return f.attribute_string("/", name);
  } catch (const std::exception&) {
  }
  try {
    std::string s;
    for (auto v : f.attribute_array<double>("/", name)) s += std::to_string(v) + ",";
    return s;
  } catch (const std::exception&) {
  }
  std::string s;
  for (auto v : f.attribute_array<std::int64_t>("/", name)) s += std::to_string(v) + ",";
  return s;
}

/// Same root attributes and, recursively, the same datasets (shape, type, every element).
void expect_same_file(const std::string& pa, const std::string& pb) {
  const H5File a = H5File::open_read(pa), b = H5File::open_read(pb);
  ASSERT_EQ(a.attribute_names("/"), b.attribute_names("/"));
  for (const auto& n : a.attribute_names("/")) EXPECT_EQ(attribute_text(a, n), attribute_text(b, n)) << n;
  test::expect_same_datasets(a, b);
}

/// The uninterrupted reference run of `sims` simulations of `family` (made once per binary run).
std::string reference(int sims, const std::string& family) {
  static std::map<std::string, std::string> made;
  const std::string key = std::to_string(sims) + family;
  if (auto it = made.find(key); it != made.end()) return it->second;
  const fs::path dir = fs::temp_directory_path() / ("dc_generate_cli_ref_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string out = (dir / ("ref" + std::to_string(made.size()) + ".h5")).string();
  const std::string cmd = std::string(DC_CLI) + " generate --sims " + std::to_string(sims) + family +
                          " --threads 1 --out " + out + " >/dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  made[key] = out;
  static const struct Cleanup {
    fs::path d;
    ~Cleanup() { fs::remove_all(d); }
  } cleanup{dir};
  return out;
}

int one_line(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

/// Committed shards of the interrupted run of OUT (final names under OUT.shards/RUN/).
int committed_shards(const std::string& out) {
  int n = 0;
  for (const auto& run : fs::directory_iterator(out + ".shards"))
    for (const auto& f : fs::directory_iterator(run.path())) n += f.path().extension() == ".h5" ? 1 : 0;
  return n;
}

TEST(GenerateCli, ThreadCountDoesNotChangeTheFile) {
  Dir dir;
  const std::string out2 = dir / "t2.h5";
  const Result r = test::run_cli("generate --sims 3" + kFamily + " --threads 2 --out " + out2);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(out2 + ".partial"));
  expect_same_file(reference(3, kFamily), out2);
  const DataSetReader data(out2);
  ASSERT_EQ(data.simulations().size(), 3u);
  EXPECT_EQ(data.simulations()[2].seed, 7u);
  EXPECT_EQ(data.feature_channels(), 5);
  EXPECT_EQ(data.nx(), 25);
}

TEST(GenerateCli, KillNineThenResumeEqualsAnUninterruptedRun) {
  Dir dir;
  const std::string out = dir / "killed.h5", err = dir / "err.txt";
  const std::string args = "generate --sims 6" + kSlow + " --threads 1 --log-completed --out " + out;
  const pid_t pid = spawn_cli(args, err, ChildLog::StderrOnly);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for(err, "completed 0 ", pid)) << slurp(err);
  ::kill(pid, SIGKILL);
  EXPECT_EQ(wait_exit(pid), -SIGKILL) << "the run finished before it could be killed";
  ASSERT_TRUE(fs::exists(out + ".partial"));
  EXPECT_FALSE(fs::exists(out));
  EXPECT_GE(committed_shards(out), 1);
  EXPECT_LT(committed_shards(out), 6);
  // Without --resume the interrupted run is never overwritten.
  const Result refused = test::run_cli(args);
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.err.find("--resume"), std::string::npos) << refused.err;
  EXPECT_EQ(one_line(refused.err), 1) << refused.err;

  const Result resumed = test::run_cli(args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_FALSE(fs::exists(out + ".partial"));
  expect_same_file(reference(6, kSlow), out);
}

TEST(GenerateCli, SigintExitsNonZeroAndLeavesAResumablePartialFile) {
  Dir dir;
  const std::string out = dir / "int.h5", err = dir / "err.txt";
  const std::string args = "generate --sims 6" + kSlow + " --threads 2 --log-completed --out " + out;
  const pid_t pid = spawn_cli(args, err, ChildLog::StderrOnly);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for(err, "completed 0 ", pid)) << slurp(err);
  ::kill(pid, SIGINT);
  const int status = wait_exit(pid);
  ASSERT_EQ(status, 130) << slurp(err);  // 128 + SIGINT, after committing what was finished
  EXPECT_NE(slurp(err).find("--resume"), std::string::npos) << slurp(err);
  ASSERT_TRUE(fs::exists(out + ".partial"));
  EXPECT_FALSE(fs::exists(out));
  EXPECT_GE(committed_shards(out), 1);
  const Result resumed = test::run_cli(args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_same_file(reference(6, kSlow), out);
}

// What batch systems send at the time limit (SIGTERM) or ahead of it (SIGUSR1) stops the run
// like Ctrl-C: what is committed stays, one line says how to resume, exit status 143.
TEST(GenerateCli, SigtermAndSigusr1CommitAndExit143) {
  for (const int signal : {SIGTERM, SIGUSR1}) {
    Dir dir;
    const std::string out = dir / "term.h5", err = dir / "err.txt";
    const std::string args = "generate --sims 6" + kSlow + " --threads 1 --log-completed --out " + out;
    const pid_t pid = spawn_cli(args, err, ChildLog::StderrOnly);
    ASSERT_TRUE(wait_for(err, "completed 0 ", pid)) << slurp(err);
    ::kill(pid, signal);
    ASSERT_EQ(wait_exit(pid), 143) << slurp(err);
    const std::string log = slurp(err);
    EXPECT_NE(log.find(signal == SIGTERM ? "interrupted by SIGTERM" : "interrupted by SIGUSR1"), std::string::npos)
        << log;
    EXPECT_GE(committed_shards(out), 1);
    const Result resumed = test::run_cli(args + " --resume");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    expect_same_file(reference(6, kSlow), out);
  }
}

// Two runs on one OUT — here a second --resume while the first runs, with HDF5's own file
// locking off as on many cluster file systems — never interleave: the second is refused by
// OUT.lock with one line naming the holder, and the first completes the reference data set.
TEST(GenerateCli, ASecondRunOnTheSameOutIsRefusedByTheLock) {
  Dir dir;
  const std::string out = dir / "lock.h5", err = dir / "err.txt";
  const std::string args = "generate --sims 6" + kSlow + " --threads 1 --log-completed --out " + out;
  ::setenv("HDF5_USE_FILE_LOCKING", "FALSE", 1);
  const pid_t pid = spawn_cli(args, err, ChildLog::StderrOnly);
  ASSERT_TRUE(wait_for(err, "completed 0 ", pid)) << slurp(err);
  const Result second = test::run_cli(args + " --resume");
  ::unsetenv("HDF5_USE_FILE_LOCKING");
  EXPECT_EQ(second.exit_code, 1);
  EXPECT_NE(second.err.find("is being written by pid " + std::to_string(pid) + " on host"), std::string::npos)
      << second.err;
  EXPECT_EQ(one_line(second.err), 1) << second.err;
  ASSERT_EQ(wait_exit(pid), 0) << slurp(err);
  expect_same_file(reference(6, kSlow), out);
}

TEST(GenerateCli, ResumeWithOtherParametersIsRefused) {
  Dir dir;
  const std::string out = dir / "p.h5", err = dir / "err.txt";
  const std::string args = "generate --sims 6" + kSlow + " --threads 1 --log-completed --out " + out;
  const pid_t pid = spawn_cli(args, err, ChildLog::StderrOnly);
  ASSERT_TRUE(wait_for(err, "completed 0 ", pid)) << slurp(err);
  ::kill(pid, SIGKILL);
  wait_exit(pid);
  ASSERT_TRUE(fs::exists(out + ".partial"));
  const Result r = test::run_cli("generate --sims 6" + kScene + " --count 10..15 --steps 250 --resume --out " + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--count"), std::string::npos) << r.err;
  EXPECT_EQ(one_line(r.err), 1) << r.err;
}

// The manifest's virtual datasets keep their shard mappings in HDF5's global heap ("GCOL"),
// which has no checksum. These flips of the manifest of this very command made libhdf5 1.10.8
// kill the reader: byte GCOL + 1395 bit 4 aborted it ("buffer overflow detected" in
// H5S_select_deserialize), + 1540 bit 3 and + 2428 bit 0 crashed it (SIGSEGV) — found by
// scripts/bitflip-test.sh. The manifest now carries a hash of all its bytes, checked before
// libhdf5 opens it: a one-line error, exit 1.
TEST(GenerateCli, ManifestFlipsThatCrashedLibhdf5AreOneLineErrors) {
  Dir dir;
  const std::string out = dir / "data.h5";
  ASSERT_EQ(test::run_cli("generate --sims 2 --steps 60 --seed 7 --threads 1 --out " + out).exit_code, 0);
  const std::string bytes = test::slurp_file(out);
  const std::size_t heap = bytes.find("GCOL");
  ASSERT_NE(heap, std::string::npos);
  for (const auto& [offset, bit] : {std::pair{1395, 4}, std::pair{1540, 3}, std::pair{2428, 0}}) {
    ASSERT_LT(heap + offset, bytes.size());
    std::string damaged = bytes;
    damaged[heap + offset] = static_cast<char>(damaged[heap + offset] ^ (1 << bit));
    std::ofstream(out, std::ios::binary | std::ios::trunc) << damaged;
    const Result r = test::run_cli("train --data " + out + " --out " + (dir / "m.h5") + " --epochs 1 --threads 1");
    EXPECT_EQ(r.exit_code, 1) << "GCOL + " << offset << " bit " << bit << ": " << r.err;
    EXPECT_NE(r.err.find("checksum mismatch: the file is damaged"), std::string::npos) << r.err;
    EXPECT_EQ(one_line(r.err), 1) << r.err;
  }
}

TEST(GenerateCli, BadInputsFailWithOneLine) {
  Dir dir;
  const std::string out = dir / "bad.h5";
  for (const std::string bad : {"--sims 0", "--sims 2 --count 5..2", "--sims 2 --count abc",
                                 "--sims 2 --channels mass,speed", "--sims 2 --grid poly6:0:0.5",
                                 "--sims 2 --resume", "--sims 2 --oracle lemke"}) {
    const Result r = test::run_cli("generate " + bad + " --steps 5 --out " + out);
    EXPECT_NE(r.exit_code, 0) << bad;
    EXPECT_EQ(one_line(r.err), 1) << bad << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << bad;
  }
  // An existing OUT needs --force.
  { std::ofstream(out) << "x"; }
  const Result r = test::run_cli("generate --sims 1 --steps 5 --out " + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
  EXPECT_EQ(one_line(r.err), 1) << r.err;
}

}  // namespace
}  // namespace dc
