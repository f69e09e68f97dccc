// Output paths checked before the work, and directories replaced all or nothing
// (dc/io/output_path.hpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <utility>
#include <sys/stat.h>

#include "dc/core/error.hpp"
#include "io/io_error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/output_path.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

using test::io_error;

void expect_names(const std::string& message, const std::string& path, const std::string& cause) {
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find(cause), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(OutputPath, AFileNeedsAWritableParentAndIsNoDirectory) {
  test::TempDir dir;
  check_output_file(dir / "new.h5");  // fine: the parent exists and is writable
  std::ofstream(dir / "old.h5") << "x";
  check_output_file(dir / "old.h5");  // fine: replaced atomically later
  expect_names(io_error([&] { check_output_file(dir / "a/b.h5"); }), dir / "a/b.h5", "does not exist");
  expect_names(io_error([&] { check_output_file(dir.path().string()); }), dir.path().string(), "is a directory");
  expect_names(io_error([&] { check_output_file(dir / "old.h5/x.h5"); }), dir / "old.h5/x.h5", "is not a directory");
  expect_names(io_error([&] { check_output_file("/proc/x.h5"); }), "/proc/x.h5", "cannot create files in /proc");
  expect_names(io_error([&] { check_output_file(""); }), "output file", "empty");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator{}), 1) << "probe files left";
}

TEST(OutputPath, ADirectoryNeedsAWritableParentAndIsNoFile) {
  test::TempDir dir;
  check_output_directory(dir / "new");
  check_output_directory(dir.path().string());  // an existing directory: replaced later
  std::ofstream(dir / "file") << "x";
  expect_names(io_error([&] { check_output_directory(dir / "file"); }), dir / "file", "is not a directory");
  expect_names(io_error([&] { check_output_directory(dir / "a/b"); }), dir / "a/b", "does not exist");
  expect_names(io_error([&] { check_output_directory("/proc/report"); }), "/proc/report", "cannot create files");
}

std::string slurp_text(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The names a test command writes.
bool owned(const std::string& name) { return name == "new.txt" || name == "old.txt"; }

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}));
}

TEST(OutputPath, ADirectoryHoldingOtherFilesIsRefusedNamingOne) {
  test::TempDir dir;
  const std::string out = dir / "report";
  check_owned_directory(out, owned, "the test");  // new
  fs::create_directory(out);
  check_owned_directory(out, owned, "the test");  // empty
  std::ofstream(out + "/old.txt") << "old";
  fs::create_directory(out + "/partial-run-1-0");  // what a killed run leaves
  check_owned_directory(out, owned, "the test");  // an earlier output
  fs::create_directory(out + "/mydata");
  expect_names(io_error([&] { check_owned_directory(out, owned, "the test"); }), "mydata", "the test did not write");
}

TEST(OutputPath, AnEarlierOutputIsReplacedOnlyByACompleteNewOne) {
  test::TempDir dir;
  const std::string out = dir / "report";
  fs::create_directory(out);
  std::ofstream(out + "/old.txt") << "old";
  fs::create_directory(out + "/partial-run-1-0");
  // A writer that fails half-way leaves the old directory exactly as it was, and no staging.
  EXPECT_THROW(write_into_owned_directory(out, owned,
                                          [](const std::string& staging) {
                                            std::ofstream(staging + "/new.txt") << "half";
                                            throw IoError("disk full");
                                          }),
               IoError);
  EXPECT_EQ(slurp_text(out + "/old.txt"), "old");
  EXPECT_FALSE(fs::exists(out + "/new.txt"));
  EXPECT_EQ(entries(out), 2u);
  // A complete one replaces it: nothing of the old one is left, stale partial runs included.
  write_into_owned_directory(out, owned, [](const std::string& staging) { std::ofstream(staging + "/new.txt") << "new"; });
  EXPECT_EQ(slurp_text(out + "/new.txt"), "new");
  EXPECT_EQ(entries(out), 1u);
  // A directory that did not exist is created; one a failed write created is removed again.
  write_into_owned_directory(dir / "fresh", owned, [](const std::string& staging) { std::ofstream(staging + "/new.txt") << "a"; });
  EXPECT_TRUE(fs::exists(dir / "fresh/new.txt"));
  EXPECT_THROW(write_into_owned_directory(dir / "failed", owned, [](const std::string&) { throw IoError("disk full"); }),
               IoError);
  EXPECT_EQ(entries(dir.path()), 2u);
}

TEST(OutputPath, AnOutputDirectoryFollowsTheUmask) {
  test::TempDir dir;
  const mode_t old = ::umask(027);
  write_into_owned_directory(dir / "d", owned, [](const std::string& staging) { std::ofstream(staging + "/new.txt") << "a"; });
  ::umask(old);
  struct stat st {};
  ASSERT_EQ(::stat((dir / "d").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0750u);
}

// An output file gets 0666 less the umask, as any file a program creates (and as libhdf5's).
TEST(OutputPath, AnOutputFileFollowsTheUmask) {
  test::TempDir dir;
  for (const auto& [mask, mode] : {std::pair<mode_t, mode_t>{002, 0664}, {022, 0644}, {077, 0600}}) {
    const mode_t old = ::umask(mask);
    write_file_atomically(dir / "out.json", "{}");
    ::umask(old);
    struct stat st {};
    ASSERT_EQ(::stat((dir / "out.json").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, mode) << "umask " << mask;
  }
}

}  // namespace
}  // namespace dc
