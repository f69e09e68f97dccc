// libFuzzer harness: scene TOML parser (dc::parse_scene) and --set overrides
// (dc::apply_override).
//
// Input layout: the TOML text, optionally followed by NUL-separated override assignments
// ("text\0world.width=5\0contact.friction=[1]"), so one input exercises both entry points.
// Properties: only ConfigError escapes the parser/overrides (IoError/InvalidArgument are
// tolerated but not expected); a parsed definition validates; and it round-trips
// exactly through scene_to_toml → parse_scene (the writer's documented guarantee).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t nul = all.find('\0', start);
    parts.push_back(all.substr(start, nul == std::string_view::npos ? std::string_view::npos : nul - start));
    if (nul == std::string_view::npos) break;
    start = nul + 1;
  }
  dc::WorldDef def;
  try {
    def = dc::parse_scene(parts[0], "fuzz.toml");
  } catch (const dc::ConfigError&) {
    return 0;
  } catch (const dc::IoError&) {
    return 0;
  } catch (const dc::InvalidArgument&) {
    return 0;
  }
  for (std::size_t i = 1; i < parts.size(); ++i) {
    try {
      dc::apply_override(def, parts[i]);
    } catch (const dc::ConfigError&) {
    } catch (const dc::InvalidArgument&) {
    }
  }
  try {
    def.validate();
  } catch (const dc::ConfigError&) {
    dc::fuzz::property_failed("a parsed (and overridden) scene does not validate");
  }
  dc::WorldDef again;
  try {
    again = dc::parse_scene(dc::scene_to_toml(def), "round-trip.toml");
  } catch (const dc::ConfigError&) {
    dc::fuzz::property_failed("scene_to_toml wrote a document parse_scene rejects");
  }
  if (!(again == def)) dc::fuzz::property_failed("scene_to_toml -> parse_scene is not the identity");
  return 0;
}
