#include "commands/cli_common.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>

#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/core/install_paths.hpp"

namespace dc::cli {

void SceneArgs::add_options(CLI::App& cmd) {
  cmd.add_option("--scene", file,
                 "Scene file (TOML, docs/scenes.md) or the name of a shipped scene (e.g. hopper, impact); default: the seed scene");
  cmd.add_option("--set", sets, "Override a scene key: section.key=value (repeatable), e.g. --set time.dt=0.005");
}

WorldDef SceneArgs::load() const {
  WorldDef d = file.empty() ? WorldDef{} : load_scene(file);
  for (const auto& s : sets) apply_override(d, s);
  d.validate();
  return d;
}

void check_output_extension(const std::string& option, const std::string& path,
                            const std::vector<std::string>& extensions, const std::string& what) {
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const auto& e : extensions)
    if (lower.size() > e.size() && lower.compare(lower.size() - e.size(), e.size(), e) == 0) return;
  std::string list;
  for (std::size_t i = 0; i < extensions.size(); ++i)
    list += (i == 0 ? "" : i + 1 == extensions.size() ? " or " : ", ") + extensions[i];
  throw ConfigError(option + " " + path + ": expected a name ending in " + list + " (" + what + ")");
}

/// The shipped model (docs/learning.md "Default model"), found relative to the executable
/// (dc::data_path: the install prefix or the build tree).
std::filesystem::path shipped_model() { return data_path("models/default.h5"); }

}  // namespace dc::cli
