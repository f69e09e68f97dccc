// Output paths checked before the work, and directories replaced all or nothing
// (dc/io/output_path.hpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "dc/core/error.hpp"
#include "io/io_error.hpp"
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

TEST(OutputPath, ADirectoryIsReplacedOnlyByACompleteNewOne) {
  test::TempDir dir;
  const std::string out = dir / "report";
  fs::create_directory(out);
  std::ofstream(out + "/old.txt") << "old";
  // A writer that fails half-way leaves the old directory exactly as it was, and no staging.
  EXPECT_THROW(write_directory_atomically(out,
                                          [](const std::string& staging) {
                                            std::ofstream(staging + "/new.txt") << "half";
                                            throw IoError("disk full");
                                          }),
               IoError);
  EXPECT_TRUE(fs::exists(out + "/old.txt"));
  EXPECT_FALSE(fs::exists(out + "/new.txt"));
  // A complete one replaces it: nothing of the old one is left.
  write_directory_atomically(out, [](const std::string& staging) { std::ofstream(staging + "/new.txt") << "new"; });
  EXPECT_TRUE(fs::exists(out + "/new.txt"));
  EXPECT_FALSE(fs::exists(out + "/old.txt"));
  // A directory that did not exist yet is created the same way.
  write_directory_atomically(dir / "fresh", [](const std::string& staging) { std::ofstream(staging + "/a") << "a"; });
  EXPECT_TRUE(fs::exists(dir / "fresh/a"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator{}), 2) << "staging left behind";
}

}  // namespace
}  // namespace dc
