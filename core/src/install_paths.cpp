#include "dc/core/install_paths.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <vector>

#include "dc/core/error.hpp"
#include "dc_build_info.hpp"  // generated at build time (cmake/build_info.cmake)

namespace dc {
namespace fs = std::filesystem;
namespace {

/// The directory of the binary this function is linked into: the executable, or a shared
/// module such as the Python extension (where /proc/self/exe would be the interpreter).
fs::path this_binary_dir() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&this_binary_dir), &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code ec;
  const fs::path p = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path{} : p.parent_path();
}

fs::path executable_dir() {
  std::error_code ec;
  const fs::path p = fs::canonical("/proc/self/exe", ec);
  return ec ? fs::path{} : p.parent_path();
}

/// The data root, or empty; `tried` gets every place looked at (in order).
fs::path find_data_root(std::vector<fs::path>& tried) {
  if (const char* env = std::getenv("DEEPCONTACT_DATA_DIR"); env != nullptr && *env != '\0') return env;
  for (const fs::path& dir : {this_binary_dir(), executable_dir()}) {
    if (dir.empty()) continue;
    for (const fs::path& candidate : {dir / "data", dir / ".." / "share" / "deepcontact"}) {
      std::error_code ec;
      if (fs::is_directory(candidate / "models", ec)) return fs::weakly_canonical(candidate, ec);
      tried.push_back(candidate.lexically_normal());
    }
  }
  return {};
}

}  // namespace

fs::path data_root() {
  std::vector<fs::path> tried;
  if (fs::path root = find_data_root(tried); !root.empty()) return root;
  std::string where;
  for (const auto& t : tried) where += (where.empty() ? "" : ", ") + t.string();
  throw IoError("cannot find the shipped data (models/, scenes/, plot scripts): looked in " +
                (where.empty() ? std::string("no directory") : where) + "; set DEEPCONTACT_DATA_DIR");
}

fs::path data_path(std::string_view relative) {
  std::vector<fs::path> tried;
  fs::path root = find_data_root(tried);
  if (root.empty() && tried.size() > 1) root = tried[1];  // <dir>/../share/deepcontact
  return root / fs::path(relative);
}

std::string git_commit() { return DC_GIT_COMMIT; }

std::string version() { return DC_VERSION; }

}  // namespace dc
