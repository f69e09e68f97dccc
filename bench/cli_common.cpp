#include "cli_common.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <sstream>

#include "dc/engine/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/learning/cnn_warm_starter.hpp"

namespace dc::cli {

void SceneArgs::add_options(CLI::App& cmd) {
  cmd.add_option("--scene", file, "Scene file (TOML, docs/scenes.md); default: the seed scene");
  cmd.add_option("--set", sets, "Override a scene key: section.key=value (repeatable), e.g. --set time.dt=0.005");
}

WorldDef SceneArgs::load() const {
  WorldDef d = file.empty() ? WorldDef{} : load_scene(file);
  for (const auto& s : sets) apply_override(d, s);
  d.validate();
  return d;
}

std::vector<std::uint64_t> parse_seed_range(const std::string& text) {
  auto num = [&](const std::string& s) {
    std::size_t used = 0;
    unsigned long long v = 0;
    try {
      if (s.empty() || s[0] == '-') throw ConfigError("");
      v = std::stoull(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != s.size() || s.empty())
      throw ConfigError("--seeds '" + text + "': expected A..B, A,B,C or A with non-negative integers");
    return static_cast<std::uint64_t>(v);
  };
  std::vector<std::uint64_t> out;
  if (const auto dots = text.find(".."); dots != std::string::npos) {
    const auto a = num(text.substr(0, dots)), b = num(text.substr(dots + 2));
    if (b < a) throw ConfigError("--seeds '" + text + "': empty range");
    if (b - a > 100000) throw ConfigError("--seeds '" + text + "': more than 100000 seeds");
    for (auto s = a; s <= b; ++s) out.push_back(s);
  } else {
    for (const auto& item : split_list(text)) out.push_back(num(item));
  }
  if (out.empty()) throw ConfigError("--seeds: no seeds given");
  return out;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b == std::string::npos) throw ConfigError("empty item in list '" + text + "'");
    out.push_back(item.substr(b, e - b + 1));
  }
  if (out.empty()) throw ConfigError("empty list");
  return out;
}

/// The shipped model (docs/learning.md "Default model"), found through the source tree the
/// executable was built from.
static std::filesystem::path shipped_model() { return std::filesystem::path(DC_SOURCE_DIR) / "models" / "default.h5"; }

WarmStarterRegistry full_warm_starter_registry() {
  WarmStarterRegistry r = default_warm_starters();
  add_cnn_warm_starters(r, shipped_model());
  return r;
}

std::vector<std::string> default_bench_starters(const WarmStarterRegistry& registry, bool quick) {
  std::vector<std::string> out = {"zero",    "builtin",  "builtin-extrapolate", "builtin-statics", "copy",
                                  "copy:2",  "copy:0",   "copy-noise:0.01",     "copy-noise:0.1",  "sph",
                                  "sph-prev", "random",  "bad"};
  if (quick) out = {"zero", "builtin", "copy", "sph"};
  // cnn only when the shipped model is there (a checkout without it still benches the rest;
  // `--warmstarts cnn --model F` selects another model explicitly).
  if (registry.contains("cnn") && std::filesystem::exists(shipped_model())) out.push_back("cnn");
  return out;
}

}  // namespace dc::cli
