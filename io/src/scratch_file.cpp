#include "dc/io/scratch_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "dc/core/error.hpp"

namespace dc {
namespace {

std::string default_dir() {
  const char* t = std::getenv("TMPDIR");
  return t && *t ? t : "/tmp";
}

std::string failure(const std::string& what, const std::string& dir) {
  return "scratch file in " + dir + ": " + what + ": " + std::strerror(errno);
}

}  // namespace

ScratchFile::ScratchFile(const std::string& dir) : dir_(dir.empty() ? default_dir() : dir) {
#ifdef O_TMPFILE
  fd_ = ::open(dir_.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
#endif
  if (fd_ < 0) {  // no O_TMPFILE (or a file system without it): a named file, unlinked at once
    std::string name = dir_ + "/.deepcontact-scratch-XXXXXX";
    std::vector<char> buf(name.begin(), name.end());
    buf.push_back('\0');
    fd_ = ::mkstemp(buf.data());
    if (fd_ < 0) throw IoError(failure("cannot create a temporary file", dir_));
    ::unlink(buf.data());
  }
}

ScratchFile::~ScratchFile() {
  if (fd_ >= 0) ::close(fd_);
}

std::uint64_t ScratchFile::append(const void* bytes, std::size_t n) {
  std::uint64_t at = 0;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    at = end_;
    end_ += n;
  }
  const char* p = static_cast<const char*>(bytes);
  for (std::size_t done = 0; done < n;) {
    const ssize_t w = ::pwrite(fd_, p + done, n - done, static_cast<off_t>(at + done));
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw IoError(failure("cannot write " + std::to_string(n) + " bytes", dir_));
    done += static_cast<std::size_t>(w);
  }
  return at;
}

void ScratchFile::read(std::uint64_t offset, void* out, std::size_t n) const {
  char* p = static_cast<char*>(out);
  for (std::size_t done = 0; done < n;) {
    const ssize_t r = ::pread(fd_, p + done, n - done, static_cast<off_t>(offset + done));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) {
      if (r == 0) errno = EIO;  // a short file: bytes we never wrote
      throw IoError(failure("cannot read " + std::to_string(n) + " bytes at " + std::to_string(offset), dir_));
    }
    done += static_cast<std::size_t>(r);
  }
}

std::uint64_t ScratchFile::size() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return end_;
}

}  // namespace dc
