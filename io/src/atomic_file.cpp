#include "dc/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "dc/core/error.hpp"

namespace dc {
namespace {

/// Writes all of `bytes` to `fd` (write(2) may write less than asked); false with errno set.
bool write_all(int fd, std::string_view bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

std::string parent_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace

void sync_path(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError(path + ": cannot open to sync: " + std::strerror(errno));
  // EINVAL: the file system does not support fsync on this kind of object (some do not for
  // directories); nothing more can be done there, and the data itself was synced.
  const bool ok = ::fsync(fd) == 0 || errno == EINVAL;
  const int err = errno;
  ::close(fd);
  if (!ok) throw IoError(path + ": cannot sync: " + std::strerror(err));
}

void durable_rename(const std::string& from, const std::string& to) {
  if (std::rename(from.c_str(), to.c_str()) != 0)
    throw IoError(to + ": cannot rename " + from + " onto it: " + std::strerror(errno));
  sync_path(parent_of(to));
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
  const std::string tmp = path + ".tmp";
  // 0666 less the umask, as for any file a program creates (and as libhdf5 creates its files).
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw IoError(tmp + ": cannot open for writing: " + std::strerror(errno));
  // fsync before the rename: without it a crash of the machine can leave the new name on an
  // empty or partial file (ext4's delayed allocation). A failing fsync or close (the last
  // blocks on a full disk) counts as a failed write.
  const bool written = write_all(fd, bytes) && ::fsync(fd) == 0;
  const int write_errno = errno;
  const bool closed = ::close(fd) == 0;
  if (!written || !closed) {
    const int err = !written ? write_errno : errno;
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw IoError(path + ": cannot write: " + std::strerror(err));
  }
  try {
    durable_rename(tmp, path);
  } catch (const IoError&) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
}

}  // namespace dc
