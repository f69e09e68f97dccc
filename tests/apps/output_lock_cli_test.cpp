// OUT.lock in `train` and `bench --out DIR`: while another process holds the lock on the
// output, a second run is refused at once — before it reads data or runs anything — with one
// line naming the holder, and leaves the output alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "apps/cli_helpers.hpp"
#include "dc/io/output_lock.hpp"

namespace dc {
namespace {

TEST(OutputLockCli, ASecondTrainOnTheSameOutIsRefused) {
  test::TempDir dir;
  const std::string out = (dir.path() / "model.h5").string();
  const OutputLock held(out);  // as a running train would hold it
  // The data set does not exist: the lock is checked before anything is read.
  const auto r = test::run_cli("train --data " + (dir.path() / "none.h5").string() + " --out " + out);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("is being written by pid"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(OutputLockCli, ASecondBenchOnTheSameDirIsRefused) {
  test::TempDir dir;
  const std::filesystem::path out = dir.path() / "results";
  std::filesystem::create_directories(out);
  std::ofstream(out / "report.md") << "the first run's\n";
  const OutputLock held(out.string());
  const auto r = test::run_cli("bench --quick --out " + out.string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("is being written by pid"), std::string::npos) << r.err;
  EXPECT_EQ(test::slurp((out / "report.md").string()), "the first run's\n");
}

}  // namespace
}  // namespace dc
