#pragma once
// The table of scene-file keys (private to the scene reader/writer). Each entry maps one
// TOML key `[section] key` to the WorldDef field it sets, so parsing, `--set` overrides and
// scene_to_toml() cannot drift apart. Order = order of sections and keys in written files.
#include <array>
#include <optional>
#include <vector>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "dc/engine/world_def.hpp"

namespace dc::scene_detail {

/// How a key's TOML value is read (the field type in Ref says what it becomes: a String key
/// sets a std::string or one of the named enumerations, parsed from the string).
enum class Kind { Number, Int, Seed, String, Vec2, Walls, Points, OptionalVec2, Region };

/// Accessor of the field a key sets, one alternative per field type. Plain function
/// pointers (captureless lambdas) keep the table constexpr-friendly and cheap to copy.
template <class Owner>
using Ref = std::variant<double& (*)(Owner&), int& (*)(Owner&), std::uint64_t& (*)(Owner&),
                         std::string& (*)(Owner&), Vec2& (*)(Owner&), std::array<bool, 4>& (*)(Owner&),
                         std::vector<Vec2>& (*)(Owner&), std::optional<Vec2>& (*)(Owner&),
                         std::array<double, 4>& (*)(Owner&), SolverId& (*)(Owner&), BodyShape& (*)(Owner&),
                         Motion& (*)(Owner&), BodyOrder& (*)(Owner&), InternalOrder& (*)(Owner&)>;

struct SectionKey {
  std::string_view section;
  std::string_view key;
  Kind kind;
  Ref<WorldDef> ref;
  std::string_view doc;  ///< unit and meaning, written as a comment by scene_to_toml
};

struct BodyKey {
  std::string_view key;
  Kind kind;
  Ref<BodyDef> ref;
};

std::span<const SectionKey> section_keys();
std::span<const BodyKey> body_keys();
/// Wall names in the order of WorldSection::walls.
const std::array<std::string_view, 4>& wall_names();

}  // namespace dc::scene_detail
