#include "dc/io/output_path.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "dc/core/error.hpp"

namespace dc {

namespace fs = std::filesystem;

namespace {

/// The directory a path lives in ("." for a bare name).
fs::path parent_of(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

/// Creates a new empty directory named `prefix` + 6 random characters (mkdtemp) and returns
/// its name; "" with errno set on failure.
std::string make_unique_directory(const std::string& prefix) {
  std::string name = prefix + "XXXXXX";
  return ::mkdtemp(name.data()) != nullptr ? name : std::string();
}

std::string without_trailing_slashes(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

/// IoError "`what`: `cause`" unless `dir` is an existing directory in which files can be made.
void require_writable_directory(const fs::path& dir, const std::string& what) {
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (!fs::exists(st)) throw IoError(what + ": directory " + dir.string() + " does not exist");
  if (!fs::is_directory(st)) throw IoError(what + ": " + dir.string() + " is not a directory");
  // Create a probe file: access(W_OK) is true for root even on a read-only mount.
  std::string probe = (dir / ".dc-write-probe-XXXXXX").string();
  const int fd = ::mkstemp(probe.data());  // a new, uniquely named file (O_EXCL)
  if (fd < 0) throw IoError(what + ": cannot create files in " + dir.string() + ": " + std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace

void check_output_file(const std::string& path) {
  if (path.empty()) throw IoError("output file: the path is empty");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw IoError(path + ": is a directory, but a file is to be written there");
  if (!path.empty() && path.back() == '/') throw IoError(path + ": names a directory, but a file is to be written there");
  require_writable_directory(parent_of(path), path + ": cannot write the output file");
}

void check_output_directory(const std::string& path) {
  if (path.empty()) throw IoError("output directory: the path is empty");
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec))
    throw IoError(path + ": exists and is not a directory, but an output directory is to be written there");
  require_writable_directory(parent_of(without_trailing_slashes(path)), path + ": cannot write the output directory");
}

std::string make_staging_directory(const std::string& dir) {
  const std::string target = without_trailing_slashes(dir);
  const std::string staging = make_unique_directory(target + ".tmp-");
  if (staging.empty()) throw IoError(target + ": cannot create a staging directory next to it: " + std::strerror(errno));
  return staging;
}

void replace_directory_atomically(const std::string& staging, const std::string& dir) {
  const std::string target = without_trailing_slashes(dir);
  std::error_code ec;
  std::string aside;
  if (fs::exists(target, ec)) {
    // rename(2) may replace an empty directory: reserve a unique empty one, move DIR onto it.
    aside = make_unique_directory(target + ".old-");
    if (aside.empty()) throw IoError(target + ": cannot reserve a name to move the earlier output aside: " + std::strerror(errno));
    fs::rename(target, aside, ec);
    if (ec) throw IoError(target + ": cannot move the earlier output aside: " + ec.message());
  }
  fs::rename(staging, target, ec);
  if (ec) {
    std::error_code ignored;
    if (!aside.empty()) fs::rename(aside, target, ignored);
    throw IoError(target + ": cannot rename " + staging + " onto it: " + ec.message());
  }
  if (!aside.empty()) fs::remove_all(aside, ec);  // best effort: the new DIR is already in place
}

void write_directory_atomically(const std::string& dir, const std::function<void(const std::string&)>& write) {
  const std::string staging = make_staging_directory(dir);
  try {
    write(staging);
    replace_directory_atomically(staging, dir);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
}

}  // namespace dc
