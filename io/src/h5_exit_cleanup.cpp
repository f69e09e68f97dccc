// libhdf5's exit-time cleanup and the files this layer abandons after a failed write
// (h5.hpp: h5_skip_exit_cleanup, h5_cleanup_at_exit_unless_abandoned, h5_abandoned_file_open).
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "dc/io/h5.hpp"
#include "h5_detail.hpp"

namespace dc {
namespace {

/// The atexit handler of h5_cleanup_at_exit_unless_abandoned: what libhdf5 would have done
/// (H5close), unless it would crash on a file it cannot close.
void close_library_unless_abandoned() {
  if (!h5_abandoned_file_open()) H5close();
}

}  // namespace

bool h5_skip_exit_cleanup() { return H5dont_atexit() >= 0; }

bool h5_cleanup_at_exit_unless_abandoned() {
  if (!h5_skip_exit_cleanup()) return false;
  return std::atexit(close_library_unless_abandoned) == 0;
}

bool h5_abandoned_file_open() {
  // A sink stays open exactly as long as the abandoned file's id: its close closes the
  // descriptor. /proc/self/fd names a memfd "/memfd:NAME (deleted)".
  const std::string needle = std::string("/memfd:") + h5_detail::kAbandonedSinkName;
  std::error_code ec;
  for (std::filesystem::directory_iterator it("/proc/self/fd", ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code link_ec;
    const std::string target = std::filesystem::read_symlink(it->path(), link_ec).string();
    if (!link_ec && target.rfind(needle, 0) == 0) return true;
  }
  return false;
}

}  // namespace dc
