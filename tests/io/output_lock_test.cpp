// OutputLock (dc/io/output_lock.hpp): a second process is refused with one line naming the
// holder's pid and host; the lock goes with its holder, however the holder ends.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "dc/core/error.hpp"
#include "dc/io/output_lock.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

const std::string kTarget = (fs::temp_directory_path() / ("dc_lock_test_" + std::to_string(::getpid()))).string();

/// In a child process: 0 if it took the lock on kTarget, 1 if refused with a message naming
/// `pid` (written to `message_file`), 2 otherwise. fcntl locks belong to a process, so the
/// second taker must be another process.
int lock_in_child(pid_t holder, const std::string& message_file) {
  const pid_t child = ::fork();
  if (child == 0) {
    int code = 2;
    try {
      const OutputLock lock(kTarget);
      code = 0;
    } catch (const IoError& e) {
      std::ofstream(message_file) << e.what();
      code = std::string(e.what()).find("pid " + std::to_string(holder) + " on host ") != std::string::npos ? 1 : 2;
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 3;
}

TEST(OutputLock, SecondProcessIsRefusedWithTheHoldersPidAndHost) {
  const std::string message = kTarget + ".msg";
  {
    const OutputLock lock(kTarget);
    EXPECT_TRUE(fs::exists(kTarget + ".lock"));
    EXPECT_EQ(lock_in_child(::getpid(), message), 1);
    std::ifstream in(message);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_NE(text.find(kTarget + " is being written by pid"), std::string::npos) << text;
    EXPECT_EQ(text.find('\n'), std::string::npos) << "one line: " << text;
  }
  EXPECT_FALSE(fs::exists(kTarget + ".lock"));  // released and removed
  EXPECT_EQ(lock_in_child(::getpid(), message), 0);
  fs::remove(message);
}

// A holder killed with SIGKILL leaves OUT.lock behind, but not the lock: the next run takes it.
TEST(OutputLock, AKilledHoldersFileDoesNotBlock) {
  const pid_t child = ::fork();
  if (child == 0) {
    const OutputLock lock(kTarget);
    ::pause();
    ::_exit(0);
  }
  for (int i = 0; i < 500 && !fs::exists(kTarget + ".lock"); ++i) ::usleep(10000);
  ::usleep(50000);
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  EXPECT_TRUE(fs::exists(kTarget + ".lock"));
  EXPECT_NO_THROW(OutputLock{kTarget});
}

}  // namespace
}  // namespace dc
