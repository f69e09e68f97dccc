#pragma once
// A temporary file for data too large for RAM that is read back later in the same process
// (e.g. the bench's per-sweep θ rows). It has no name: on Linux it is opened with O_TMPFILE,
// elsewhere created with mkstemp and unlinked at once, so nothing is left on disk whatever
// ends the process (exit, exception, SIGKILL) — the kernel frees the blocks when the
// descriptor closes.
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>

namespace dc {

class ScratchFile {
 public:
  /// A new empty file in folder `dir` (empty = $TMPDIR, else /tmp). IoError naming the folder
  /// when it cannot be created there.
  explicit ScratchFile(const std::string& dir = {});
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  ~ScratchFile();

  /// Appends `n` bytes and returns their offset. Safe to call from several threads at once
  /// (each call's bytes stay contiguous). IoError on a failed write (e.g. a full disk).
  std::uint64_t append(const void* bytes, std::size_t n);
  /// Reads `n` bytes at `offset` (written by append before). IoError on failure.
  void read(std::uint64_t offset, void* out, std::size_t n) const;
  /// Bytes appended so far.
  [[nodiscard]] std::uint64_t size() const;
  /// The folder the file lives in (for messages).
  [[nodiscard]] const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  int fd_ = -1;
  mutable std::mutex mutex_;  // guards end_ (the offset handed out next)
  std::uint64_t end_ = 0;
};

}  // namespace dc
