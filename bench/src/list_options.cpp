#include "dc/bench/list_options.hpp"

#include <sstream>

#include "dc/core/error.hpp"

namespace dc::bench {

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

}  // namespace dc::bench
