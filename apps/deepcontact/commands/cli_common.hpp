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

/// The shipped model, models/default.h5 of the source tree the executable was built from: the
/// cnn starter's default and the reason the bench runs cnn by default.
std::filesystem::path shipped_model();

}  // namespace dc::cli
