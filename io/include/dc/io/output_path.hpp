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
/// non-directory; an existing DIR must be a writable directory (the outputs are built inside
/// it), a new one needs a writable parent. Whether DIR's contents may be replaced is
/// check_owned_directory's question.
void check_output_directory(const std::string& path);

/// Says whether an entry of an output directory (a bare name, e.g. "report.md") is one that
/// the command writes: only such entries are ever replaced or removed.
using OwnedName = std::function<bool(const std::string& name)>;

/// The prefix of the staging folder inside an output directory ("DIR/partial-run-PID-N"):
/// what a run killed before it finished leaves behind, under a name that says so.
inline constexpr const char* kPartialRunPrefix = "partial-run-";

/// check_output_directory, and: an existing `dir` may hold only entries `owned` accepts (an
/// earlier run's output) or partial-run folders. Otherwise IoError with one line naming the
/// first entry in the way ("DIR: holds NAME, which <what> did not write; …"), so a command
/// never deletes or replaces a file it did not write. `what` names the command.
void check_owned_directory(const std::string& dir, const OwnedName& owned, const std::string& what);

/// Writes a command's output files into `dir` (created if missing; mode 0777 less the umask,
/// like mkdir): `write(staging)` fills a fresh folder `dir/partial-run-PID-N`; when it
/// returns, the earlier entries of `dir` that `owned` accepts and this run did not write are
/// removed, each new entry is renamed into `dir` (replacing its namesake), stale partial-run
/// folders are removed and `dir` is fsynced. If `write` throws, the staging folder is removed,
/// `dir` keeps every earlier byte (a `dir` this call created is removed again) and the
/// exception propagates. Call check_owned_directory first, and hold `dir`'s OutputLock (a
/// second writer's staging folder would otherwise count as stale).
void write_into_owned_directory(const std::string& dir, const OwnedName& owned,
                                const std::function<void(const std::string& staging)>& write);

}  // namespace dc
