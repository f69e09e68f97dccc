#pragma once
// One writer per output: a lock of our own on `OUT.lock`, independent of HDF5's file locking
// (which clusters often switch off with HDF5_USE_FILE_LOCKING=FALSE because their file
// systems do not support it). Two `generate --resume` on one data set, or a `train` and a
// `train --resume` on one model, would otherwise interleave their writes.
//
// The lock is a POSIX record lock (fcntl F_SETLK on the whole of OUT.lock): released by the
// kernel when the process ends however it ends (SIGKILL included), so a stale OUT.lock never
// blocks a later run, and honoured across hosts by NFS (lockd) and the cluster file systems
// that support POSIX locks. The holder writes "pid P on host H" into the file, so the
// refused process can say who holds it.
#include <string>

namespace dc {

class OutputLock {
 public:
  /// Takes the lock on `target + ".lock"` (creating the file) without waiting. IoError with
  /// one line naming the target and the holder ("… is being written by pid 123 on host n1
  /// (OUT.lock)") when another process holds it, or when the lock file cannot be created.
  explicit OutputLock(const std::string& target);
  /// Removes OUT.lock (while still holding it) and releases the lock.
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace dc
