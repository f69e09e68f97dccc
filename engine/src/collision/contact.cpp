#include "dc/engine/contact.hpp"

#include <algorithm>
#include <string>

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
  // The sortedness checks ride along the merge pass, so each list is read in one pass (large
  // contact lists are out of cache). Every adjacent pair of each list is still compared.
  const auto unsorted = [](const char* which) {
    return InvalidArgument(std::string("match_contacts_by_key: the ") + which + " contacts are not sorted by key");
  };
  std::vector<int> out(current.size(), -1);
  std::size_t j = 0;
  const std::size_t np = previous.size();
  for (std::size_t c = 0; c < current.size(); ++c) {
    if (c > 0 && current[c].key < current[c - 1].key) throw unsorted("current");
    while (j < np && previous[j].key < current[c].key) {
      if (j + 1 < np && previous[j + 1].key < previous[j].key) throw unsorted("previous");
      ++j;
    }
    if (j < np && previous[j].key == current[c].key) out[static_cast<std::size_t>(c)] = static_cast<int>(j);
  }
  for (; j + 1 < np; ++j)
    if (previous[j + 1].key < previous[j].key) throw unsorted("previous");
  return out;
}

}  // namespace dc
