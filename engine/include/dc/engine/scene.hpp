#pragma once
// Scene files (TOML, docs/design.md §7, docs/scenes.md). Every key is optional and defaults to the
// seed scene, so an empty file is the seed scene. Unknown keys, wrong types, NaN/Inf and
// out-of-range values are ConfigErrors naming the key, e.g.
//   "scene.toml: [contact] friction: expected a number ≥ 0, got -1"
#include <string>
#include <string_view>
#include <vector>

#include "dc/engine/world_def.hpp"

namespace dc {

WorldDef parse_scene(std::string_view toml_text, std::string_view source_name = "<scene>");
/// Reads the scene file `name`, or, when no such file exists and `name` has no '/', the shipped
/// scene of that name (`hopper` or `hopper.toml` → DATA/scenes/hopper.toml, dc::data_path).
/// Throws IoError naming the file (and listing the shipped scenes when neither exists).
WorldDef load_scene(const std::string& name);
/// The path load_scene reads for `name` (the name itself when no shipped scene matches).
std::string find_scene(const std::string& name);
/// The names of the shipped scenes (DATA/scenes/*.toml without the extension), sorted.
std::vector<std::string> shipped_scenes();
/// Applies one `section.key=value` override; the value is TOML (numbers, "strings",
/// [arrays], true/false). Validates like a scene file key.
void apply_override(WorldDef& def, std::string_view assignment);
/// The definition as a complete TOML document (every key written; round-trips).
std::string scene_to_toml(const WorldDef& def);

}  // namespace dc
