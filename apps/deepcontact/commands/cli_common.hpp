#pragma once
// Pieces shared by several subcommands: scene options (--scene, --set), seed ranges, lists,
// and the shipped model.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dc/engine/world_def.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace CLI { class App; }

namespace dc::cli {

struct SceneArgs {
  std::string file;                 ///< --scene F ("" = the seed scene)
  std::vector<std::string> sets;    ///< --set section.key=value (repeatable)
  void add_options(CLI::App& cmd);
  /// The scene file (or defaults) with the overrides applied and validated.
  [[nodiscard]] WorldDef load() const;
};

/// Throws ConfigError "OPTION PATH: expected a name ending in E1 or E2 (WHAT)" unless `path`
/// ends in one of `extensions` (e.g. {".h5", ".hdf5"}; compared case-insensitively), so that a
/// file's name says what it holds (`--out run.txt` would otherwise hold HDF5).
void check_output_extension(const std::string& option, const std::string& path,
                            const std::vector<std::string>& extensions, const std::string& what);

/// The extensions of an HDF5 output: .h5, .hdf5.
inline const std::vector<std::string> kHdf5Extensions{".h5", ".hdf5"};

/// The shipped model, models/default.h5 of the source tree the executable was built from: the
/// cnn starter's default and the reason the bench runs cnn by default.
std::filesystem::path shipped_model();

}  // namespace dc::cli
