#include "world/spatial_order.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#include "dc/core/error.hpp"
#include "dc/core/number_text.hpp"

namespace dc {
namespace {

/// Spreads the 32 bits of v to the even bit positions of a 64-bit word (bit k → bit 2k).
std::uint64_t spread_bits(std::uint32_t x) {
  std::uint64_t v = x;
  v = (v | (v << 16)) & 0x0000ffff0000ffffULL;
  v = (v | (v << 8)) & 0x00ff00ff00ff00ffULL;
  v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0fULL;
  v = (v | (v << 2)) & 0x3333333333333333ULL;
  v = (v | (v << 1)) & 0x5555555555555555ULL;
  return v;
}

}  // namespace

std::uint64_t morton_code(std::uint32_t i, std::uint32_t j) { return spread_bits(i) | (spread_bits(j) << 1); }

std::vector<int> morton_order(std::span<const Vec2> centres, double cell) {
  if (!(cell > 0) || !std::isfinite(cell))
    throw InvalidArgument("morton_order: the cell side must be finite and > 0, got " + g_text(cell));
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0;
  for (const Vec2 c : centres) {
    x0 = std::min(x0, c.x);
    y0 = std::min(y0, c.y);
  }
  // Cell coordinates are clamped to 2³¹: a scene wider than that only loses locality.
  constexpr double kMaxCell = 2147483648.0;
  auto cell_of = [&](double v, double origin) {
    return static_cast<std::uint32_t>(std::min(kMaxCell, std::floor((v - origin) / cell)));
  };
  std::vector<std::pair<std::uint64_t, int>> keys(centres.size());
  for (std::size_t k = 0; k < centres.size(); ++k)
    keys[k] = {morton_code(cell_of(centres[k].x, x0), cell_of(centres[k].y, y0)), static_cast<int>(k)};
  std::sort(keys.begin(), keys.end());  // (code, index): ties in index order
  std::vector<int> order(centres.size());
  for (std::size_t k = 0; k < keys.size(); ++k) order[k] = keys[k].second;
  return order;
}

}  // namespace dc
