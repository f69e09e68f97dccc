// OutputLock: fcntl lock on OUT.lock naming its holder (output_lock.hpp).
#include "dc/io/output_lock.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "dc/core/error.hpp"

namespace dc {
namespace {

/// "pid P on host H" of the current holder, as it wrote it (empty while it has not yet).
std::string holder_of(int fd) {
  char buf[256] = {};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  std::string s = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
  while (!s.empty() && (s.back() == '\n' || s.back() == '\0')) s.pop_back();
  return s;
}

bool lock_whole_file(int fd) {
  struct flock fl {};
  fl.l_type = F_WRLCK;
  fl.l_whence = SEEK_SET;
  fl.l_start = 0;
  fl.l_len = 0;  // to the end, however long
  return ::fcntl(fd, F_SETLK, &fl) == 0;
}

}  // namespace

OutputLock::OutputLock(const std::string& target) : path_(target + ".lock") {
  // The previous holder unlinks the file while holding the lock: a lock taken on a file that
  // has been unlinked from the name (same inode check) is retried on the new file.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw IoError(path_ + ": cannot create the lock file: " + std::strerror(errno));
    if (!lock_whole_file(fd)) {
      const int err = errno;
      // The holder writes its name right after taking the lock: give it a moment.
      std::string holder = holder_of(fd);
      for (int wait = 0; holder.empty() && wait < 20; ++wait) {
        ::usleep(5000);
        holder = holder_of(fd);
      }
      ::close(fd);
      if (err != EACCES && err != EAGAIN) throw IoError(path_ + ": cannot lock: " + std::strerror(err));
      throw IoError(target + " is being written by " + (holder.empty() ? std::string("another process") : holder) +
                    " (" + path_ + "); wait for it to finish or stop it");
    }
    struct stat by_fd {}, by_name {};
    if (::fstat(fd, &by_fd) == 0 && ::stat(path_.c_str(), &by_name) == 0 && by_fd.st_ino == by_name.st_ino &&
        by_fd.st_dev == by_name.st_dev) {
      char host[256] = {};
      ::gethostname(host, sizeof host - 1);
      const std::string me = "pid " + std::to_string(::getpid()) + " on host " + host + "\n";
      if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, me.data(), me.size(), 0) != static_cast<ssize_t>(me.size())) {
        const int err = errno;
        ::close(fd);
        throw IoError(path_ + ": cannot write the lock file: " + std::strerror(err));
      }
      fd_ = fd;
      return;
    }
    ::close(fd);  // unlinked under us by the previous holder: try the new file
  }
  throw IoError(path_ + ": cannot lock: the lock file keeps being replaced");
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // still locked: a waiter that opened the old inode re-checks it
  ::close(fd_);
}

}  // namespace dc
