#pragma once
// Checking an output path before any work: a command that simulates for an hour and only then
// finds that its --out cannot be written has wasted the hour. Every command calls one of these
// on each of its outputs before it loads a scene, reads a data set or starts a simulation.
#include <functional>
#include <string>

namespace dc {

/// Throws dc::IoError with one line naming `path` and the cause unless a file can be written
/// at `path`: not empty, not an existing directory, its parent directory exists, is a
/// directory, and a file can be created in it (probed by creating and removing a uniquely
/// named empty file, so read-only file systems and permissions — also root's — are seen as
/// the writer will see them). An existing file at `path` is fine (it is replaced atomically).
void check_output_file(const std::string& path);

/// The same for an output directory (e.g. `bench --out DIR`): not empty, not an existing
/// non-directory, and its parent is a writable directory (DIR is built under a temporary
/// name next to it and renamed, so the parent is what must be writable). An existing DIR is
/// fine: it is replaced only when the new one is complete (replace_directory_atomically).
void check_output_directory(const std::string& path);

/// A fresh, empty directory next to `dir` ("DIR.tmp-XXXXXX" in DIR's parent) to build the
/// outputs in; IoError when it cannot be created.
std::string make_staging_directory(const std::string& dir);

/// Moves the finished `staging` directory onto `dir`: an existing `dir` is first renamed
/// aside ("DIR.old-XXXXXX"), then `staging` renamed onto `dir`, then the old one removed; if the
/// second rename fails the old one is put back. A reader therefore sees the old DIR or the new
/// one, never a mix of two runs (between the two renames there is an instant without DIR). A
/// kill before this call leaves DIR untouched and a stale staging directory next to it.
void replace_directory_atomically(const std::string& staging, const std::string& dir);

/// A whole output directory, all or nothing: `write(staging)` fills a staging directory next to
/// `dir` (make_staging_directory), which then replaces `dir` (replace_directory_atomically). If
/// `write` throws, the staging directory is removed, `dir` is left as it was and the exception
/// propagates. Call check_output_directory(dir) before the work that produces the content.
void write_directory_atomically(const std::string& dir, const std::function<void(const std::string& staging)>& write);

}  // namespace dc
