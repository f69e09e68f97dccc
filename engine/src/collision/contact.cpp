#include "dc/engine/contact.hpp"

#include <algorithm>

#include "dc/core/error.hpp"

namespace dc {

const char* wall_name(int id) {
  switch (id) {
    case static_cast<int>(Wall::Left): return "left";
    case static_cast<int>(Wall::Right): return "right";
    case static_cast<int>(Wall::Bottom): return "bottom";
    case static_cast<int>(Wall::Top): return "top";
    default: return id >= 0 ? "body" : "unknown-wall";
  }
}

}  // namespace dc

namespace dc {

std::vector<int> match_contacts_by_key(std::span<const Contact> previous, std::span<const Contact> current) {
  const auto by_key = [](const Contact& x, const Contact& y) { return x.key < y.key; };
  if (!std::is_sorted(previous.begin(), previous.end(), by_key))
    throw InvalidArgument("match_contacts_by_key: the previous contacts are not sorted by key");
  if (!std::is_sorted(current.begin(), current.end(), by_key))
    throw InvalidArgument("match_contacts_by_key: the current contacts are not sorted by key");
  std::vector<int> out(current.size(), -1);
  std::size_t j = 0;
  for (std::size_t c = 0; c < current.size(); ++c) {
    while (j < previous.size() && previous[j].key < current[c].key) ++j;
    if (j < previous.size() && previous[j].key == current[c].key) out[c] = static_cast<int>(j);
  }
  return out;
}

}  // namespace dc
