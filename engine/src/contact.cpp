#include "dc/engine/contact.hpp"

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
