#pragma once
// Lists as the command line and the Python bench write them: seed ranges ("1..8", "1,3,5")
// and comma-separated items.
#include <cstdint>
#include <string>
#include <vector>

namespace dc::bench {

/// "A..B" (inclusive), "A,B,C" or "A"; ConfigError on anything else or an empty range.
std::vector<std::uint64_t> parse_seed_range(const std::string& text);
/// Comma-separated items, trimmed, empty items rejected.
std::vector<std::string> split_list(const std::string& text);

}  // namespace dc::bench
