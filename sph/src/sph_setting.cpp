#include "dc/sph/sph_setting.hpp"

#include <cmath>
#include <sstream>
#include <vector>

#include "dc/core/error.hpp"

namespace dc {

SphTransferDef default_sph_setting(double width, double height) {
  SphTransferDef d;
  d.grid.width = width;
  d.grid.height = height;
  d.grid.spacing = 0.5;
  d.grid.channels = 2;
  // The best setting of `deepcontact sph-study --seeds 1..2` (docs/sph.md): poly6 with
  // h = 0.71·d, the smallest support that still reaches a node from every point of a cell
  // (h ≥ d·√2/2), so neighbouring contacts overlap least and the Shepard round trip is exact.
  d.kernel = SphKernelType::Poly6;
  d.support = 0.355;
  d.normalisation = SphNormalisation::Shepard;
  return d;
}

void parse_sph_setting(const std::string& text, SphTransferDef& def) {
  if (text.empty()) return;
  std::vector<std::string> parts;
  std::stringstream ss(text);
  for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
  if (parts.size() < 3 || parts.size() > 4)
    throw ConfigError("sph setting '" + text + "': expected KERNEL:D:H[:NORMALISATION]");
  def.kernel = parse_sph_kernel(parts[0]);
  auto number = [&](const std::string& s, const char* what) {
    try {
      std::size_t used = 0;
      const double v = std::stod(s, &used);
      if (used == s.size() && v > 0 && std::isfinite(v)) return v;
    } catch (const std::exception&) {
    }
    throw ConfigError("sph setting '" + text + "': " + what + " must be a number > 0");
  };
  def.grid.spacing = number(parts[1], "D");
  def.support = number(parts[2], "H");
  if (parts.size() == 4) def.normalisation = parse_sph_normalisation(parts[3]);
  try {
    def.validate();
  } catch (const std::exception& e) {
    throw ConfigError("sph setting '" + text + "': " + e.what());
  }
}

}  // namespace dc
