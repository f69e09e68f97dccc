#pragma once
// Where the running program finds what ships with it (models/, scenes/, the plot scripts
// bench/plots and research/plots, python/deepcontact/trajectory.py) and which commit it was
// built from. Nothing is compiled in as an absolute path, so an installed prefix can be moved
// and a build tree works as well (DEVELOPERS.md "Install"):
//
//   installed prefix P:  P/bin/deepcontact, P/lib/libdc_*.a  →  P/share/deepcontact/
//   build tree B:        B/bin/deepcontact                   →  B/share/deepcontact/ (links to
//                                                               the source folders, made by CMake)
//   Python package D:    D/_core*.so                         →  D/data/
//
// The data root keeps the source tree's relative paths: data_path("models/default.h5"),
// data_path("bench/plots/render_trajectory.py").
#include <filesystem>
#include <string>
#include <string_view>

namespace dc {

/// The data root of the running program: $DEEPCONTACT_DATA_DIR when set (non-empty), else the
/// first existing of <dir>/data and <dir>/../share/deepcontact, where <dir> is the directory of
/// the binary holding this code (the executable, or the Python extension module), then the
/// same two next to /proc/self/exe. Throws dc::IoError (one line, the places it looked) when
/// none exists.
[[nodiscard]] std::filesystem::path data_root();

/// data_root() / relative, not checked for existence. Never throws: without a data root it is
/// the path under the first place data_root() looked (<dir>/../share/deepcontact), so the
/// caller's open fails naming the file where it was expected (a plot is then skipped with a
/// warning instead of losing a finished bench).
[[nodiscard]] std::filesystem::path data_path(std::string_view relative);

/// The git commit the binary was built from: 12 hex digits, "-dirty" when tracked files
/// differed from it at build time, "unknown" outside a git checkout.
[[nodiscard]] std::string git_commit();

/// The project version (CMake's PROJECT_VERSION, e.g. "0.1.0").
[[nodiscard]] std::string version();

}  // namespace dc
