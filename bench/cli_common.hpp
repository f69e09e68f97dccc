#pragma once
// Pieces shared by several subcommands: scene options (--scene, --set), seed ranges, lists,
// and the full warm-starter registry (this library's starters plus cnn when available).
#include <cstdint>
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

/// "A..B" (inclusive), "A,B,C" or "A"; ConfigError on anything else or an empty range.
std::vector<std::uint64_t> parse_seed_range(const std::string& text);
/// Comma-separated items, trimmed, empty items rejected.
std::vector<std::string> split_list(const std::string& text);

/// default_warm_starters() plus the learning library's cnn starter.
WarmStarterRegistry full_warm_starter_registry();
/// The starters `deepcontact bench` runs by default.
std::vector<std::string> default_bench_starters(const WarmStarterRegistry& registry, bool quick);

}  // namespace dc::cli
