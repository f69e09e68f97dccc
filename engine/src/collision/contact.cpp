#include "dc/engine/contact.hpp"

#include <algorithm>
#include <string>

#include "dc/core/error.hpp"
#include "dc/engine/contact_match.hpp"

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
  std::vector<int> out(current.size(), -1);  // one merge pass, the sortedness checks riding along
  for_each_matched_contact(previous, current, [&](std::size_t c, const Contact& p) {
    out[c] = static_cast<int>(&p - previous.data());
  });
  return out;
}

}  // namespace dc
