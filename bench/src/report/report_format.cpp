#include "report_format.hpp"

#include <cmath>
#include <cstdio>

namespace dc::bench {

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace dc::bench
