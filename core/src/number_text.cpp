#include "dc/core/number_text.hpp"

#include <cstdio>

namespace dc {

std::string g_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace dc
