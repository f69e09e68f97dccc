#include "dc/warmstart/starter_support.hpp"

#include <stdexcept>
#include <string>

namespace dc {

int parse_cgls_iterations(const WarmStartSpec& spec) {
  if (spec.arg.empty()) return 100;
  std::size_t used = 0;
  int it = 0;
  try {
    it = std::stoi(spec.arg, &used);
  } catch (const std::logic_error&) {
    used = 0;
  }
  if (used != spec.arg.size() || it < 1)
    throw ConfigError("warm starter '" + spec.full() + "': expected " + spec.name + "[:ITER] with ITER >= 1");
  return it;
}


}  // namespace dc
