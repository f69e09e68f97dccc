// A program that calls h5_skip_exit_cleanup() first (deepcontact's main, the Python module)
// exits cleanly after a write failed under a file-size limit: libhdf5's own exit-time cleanup
// would crash then (h5.hpp). Each case runs in a fresh process (a "threadsafe" death test
// re-executes this binary), where HDF5 is not yet in use.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

/// Appends rows to an on-disk file under a 64 KiB file-size limit until a write fails, and
/// returns whether the failure was an IoError (the file is then abandoned).
bool fail_a_write(const std::string& path) {
  std::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead of killing the process
  const rlimit limit{64 << 10, 64 << 10};
  if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) return false;
  try {
    H5File f = H5File::create(path);
    f.create_dataset<double>("/rows", {0, 512}, {.extendible = true});
    const std::vector<double> row(512, 1.0);
    for (int i = 0; i < 1000; ++i) f.append_rows<double>("/rows", row);
  } catch (const IoError&) {
    return true;
  }
  return false;
}

TEST(H5ExitCleanup, AFailedWriteDoesNotCrashTheExit) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const test::TempDir dir;
  const std::string path = dir / "big.h5";
  EXPECT_EXIT(
      {
        if (!h5_skip_exit_cleanup()) std::_Exit(3);  // HDF5 was in use already
        if (!fail_a_write(path)) std::_Exit(4);
        std::filesystem::remove_all(dir.path());  // this process's own TempDir
        std::exit(0);                                  // runs the atexit handlers
      },
      testing::ExitedWithCode(0), "");
}

TEST(H5ExitCleanup, WithoutAFailedWriteNothingIsAbandoned) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const test::TempDir dir;
  const std::string path = dir / "small.h5";
  EXPECT_EXIT(
      {
        if (!h5_skip_exit_cleanup()) std::_Exit(3);
        {
          H5File f = H5File::create(path);
          f.write<double>("/v", std::vector<double>(4, 2.0), {4});
        }
        std::filesystem::remove_all(dir.path());
        std::exit(0);
      },
      testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace dc
