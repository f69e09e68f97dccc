#pragma once
// Writing a file so that readers never see half of it: the bytes go to `path + ".tmp"`,
// which is flushed to the device (fsync) and only then renamed onto `path`; the directory is
// fsynced after the rename, so the new name survives a power cut too. A kill at any instant
// leaves either the old `path` or the new one, never a mix (at worst a stale `path.tmp`,
// which the next write replaces). On failure (e.g. a full disk: ENOSPC, or EFBIG past a
// file-size limit) the temporary is removed and `path` keeps its content. HDF5 files
// have the same guarantee through dc::AtomicH5File (h5.hpp).
#include <string>
#include <string_view>

namespace dc {

/// Writes `bytes` to `path` atomically (tmp + fsync + rename + directory fsync, replacing an
/// existing file). Throws dc::IoError with one line naming the file when it cannot be
/// written or renamed.
void write_file_atomically(const std::string& path, std::string_view bytes);

/// fsync of an existing file or directory (a directory: its entries — created, renamed or
/// removed names — reach the device). IoError naming the path on failure.
void sync_path(const std::string& path);

/// Renames `from` onto `to` (replacing it; both in one file system), then fsyncs the
/// directory of `to`. `from` must already be synced. IoError naming both on failure.
void durable_rename(const std::string& from, const std::string& to);

}  // namespace dc
