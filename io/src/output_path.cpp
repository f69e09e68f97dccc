#include "dc/io/output_path.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <cerrno>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"

namespace dc {

namespace fs = std::filesystem;

namespace {

/// The directory a path lives in ("." for a bare name).
fs::path parent_of(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

/// Creates a new empty directory `prefix` + "PID-N" (the first free N) with mode 0777 less the
/// umask, as mkdir(1) would; "" with errno set on failure.
std::string make_unique_directory(const std::string& prefix) {
  for (int n = 0; n < 1000; ++n) {
    std::string name = prefix + std::to_string(::getpid()) + "-" + std::to_string(n);
    if (::mkdir(name.c_str(), 0777) == 0) return name;
    if (errno != EEXIST) return {};
  }
  return {};
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
  const std::string dir = without_trailing_slashes(path);
  if (fs::is_directory(dir, ec)) require_writable_directory(dir, path + ": cannot write the output directory");
  else require_writable_directory(parent_of(dir), path + ": cannot write the output directory");
}

namespace {

bool is_partial_run(const std::string& name) { return name.rfind(kPartialRunPrefix, 0) == 0; }

/// The names in `dir` (not "." or ".."); IoError naming `dir` when it cannot be listed.
std::vector<std::string> entries_of(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    names.push_back(it->path().filename().string());
  if (ec) throw IoError(dir + ": cannot list the output directory: " + ec.message());
  return names;
}

/// Moves every entry of `staging` into `dir` (replacing namesakes), then removes the owned
/// entries of `dir` that this run did not write and the stale partial-run folders.
void move_into(const std::string& staging, const std::string& dir, const OwnedName& owned) {
  const std::vector<std::string> written = entries_of(staging);
  std::error_code ec;
  for (const std::string& name : written) {
    const fs::path to = fs::path(dir) / name;
    if (fs::is_directory(to, ec)) fs::remove_all(to, ec);  // rename(2) does not replace a full folder
    fs::rename(fs::path(staging) / name, to, ec);
    if (ec) throw IoError(to.string() + ": cannot move the new output into place: " + ec.message());
  }
  fs::remove(staging, ec);
  for (const std::string& name : entries_of(dir)) {
    const bool rewritten = std::find(written.begin(), written.end(), name) != written.end();
    if ((owned(name) && !rewritten) || is_partial_run(name)) fs::remove_all(fs::path(dir) / name, ec);
  }
  sync_path(dir);
}

}  // namespace

void check_owned_directory(const std::string& dir, const OwnedName& owned, const std::string& what) {
  check_output_directory(dir);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return;
  for (const std::string& name : entries_of(dir))
    if (!owned(name) && !is_partial_run(name))
      throw IoError(without_trailing_slashes(dir) + ": holds " + name + ", which " + what +
                    " did not write; choose a new or empty directory (nothing there is replaced or removed)");
}

void write_into_owned_directory(const std::string& dir_text, const OwnedName& owned,
                                const std::function<void(const std::string&)>& write) {
  const std::string dir = without_trailing_slashes(dir_text);
  std::error_code ec;
  const bool created = fs::create_directory(dir, ec);
  if (ec) throw IoError(dir + ": cannot create the output directory: " + ec.message());
  const std::string staging = make_unique_directory((fs::path(dir) / kPartialRunPrefix).string());
  if (staging.empty()) throw IoError(dir + ": cannot create a staging folder in it: " + std::strerror(errno));
  try {
    write(staging);
    move_into(staging, dir, owned);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    if (created) fs::remove(dir, ignored);  // only when empty: nothing else is touched
    throw;
  }
}

}  // namespace dc
