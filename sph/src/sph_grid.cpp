#include "dc/sph/sph_grid.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "dc/core/error.hpp"

namespace dc {

namespace {

[[noreturn]] void bad(const char* field, double value, const char* why) {
  std::ostringstream os;
  os << "sph grid: " << field << " = " << value << ' ' << why;
  throw InvalidArgument(os.str());
}

}  // namespace

int sph_node_count(double extent, double spacing) {
  return static_cast<int>(std::floor(extent / spacing + 1e-9)) + 1;
}

void SphGridDef::validate() const {
  if (!std::isfinite(width) || width <= 0.0) bad("width", width, "must be finite and > 0");
  if (!std::isfinite(height) || height <= 0.0) bad("height", height, "must be finite and > 0");
  if (!std::isfinite(spacing) || spacing <= 0.0) bad("spacing", spacing, "must be finite and > 0");
  if (channels < 1 || channels > kMaxChannels)
    bad("channels", channels, "must be in [1, 1024]");
  // Compare in double before converting: W/d may exceed the int range.
  const double nx = std::floor(width / spacing + 1e-9) + 1.0;
  const double ny = std::floor(height / spacing + 1e-9) + 1.0;
  if (nx > kMaxNodesPerAxis) bad("spacing", spacing, "gives more than 4096 nodes along x (width / spacing too large)");
  if (ny > kMaxNodesPerAxis) bad("spacing", spacing, "gives more than 4096 nodes along y (height / spacing too large)");
  if (nx * ny * channels > static_cast<double>(1u << 28))
    bad("channels", channels, "times nx·ny exceeds 2^28 grid values");
}

SphGrid::SphGrid(const SphGridDef& def) : def_(def) {
  def_.validate();
  nx_ = sph_node_count(def_.width, def_.spacing);
  ny_ = sph_node_count(def_.height, def_.spacing);
  data_.assign(static_cast<std::size_t>(def_.channels) * nodes(), 0.0);
}

std::span<double> SphGrid::channel(int c) {
  return std::span<double>(data_).subspan(static_cast<std::size_t>(c) * nodes(), nodes());
}

std::span<const double> SphGrid::channel(int c) const {
  return std::span<const double>(data_).subspan(static_cast<std::size_t>(c) * nodes(), nodes());
}

void SphGrid::fill(double v) { std::fill(data_.begin(), data_.end(), v); }

BilinearStencil SphGrid::stencil(Vec2 p) const {
  // u = x/d clamped to [0, nx−1]; i0 = ⌊u⌋ but at most nx−2 so that i0+1 is a node and a
  // point on the last column gets fx = 1 (weight on i1) rather than an out-of-range i0+1.
  auto axis = [](double coord, double d, int n, int& lo, int& hi, double& f) {
    double u = coord / d;
    if (!(u > 0.0)) u = 0.0;  // also NaN → 0
    const double top = static_cast<double>(n - 1);
    if (u > top) u = top;
    if (n < 2) { lo = hi = 0; f = 0.0; return; }
    lo = std::min(static_cast<int>(u), n - 2);
    hi = lo + 1;
    f = u - lo;
  };
  BilinearStencil s;
  axis(p.x, def_.spacing, nx_, s.i0, s.i1, s.fx);
  axis(p.y, def_.spacing, ny_, s.j0, s.j1, s.fy);
  return s;
}

}  // namespace dc
