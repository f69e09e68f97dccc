#include "dc/sph/sph_transfer.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "dc/core/error.hpp"

namespace dc {

const char* to_string(SphNormalisation mode) {
  switch (mode) {
    case SphNormalisation::None: return "none";
    case SphNormalisation::SumToOneLegacy: return "sum-to-one-legacy";
    case SphNormalisation::Shepard: return "shepard";
  }
  return "unknown";
}

SphNormalisation parse_sph_normalisation(std::string_view name) {
  if (name == "none") return SphNormalisation::None;
  if (name == "sum-to-one-legacy" || name == "legacy") return SphNormalisation::SumToOneLegacy;
  if (name == "shepard") return SphNormalisation::Shepard;
  throw ConfigError("unknown sph normalisation '" + std::string(name) +
                    "' (available: none sum-to-one-legacy shepard)");
}

void SphTransferDef::validate() const {
  grid.validate();
  if (!std::isfinite(support) || support <= 0.0) {
    std::ostringstream os;
    os << "sph transfer: support h = " << support << " must be finite and > 0";
    throw InvalidArgument(os.str());
  }
  if (!std::isfinite(min_weight_ratio) || min_weight_ratio < 0.0) {
    std::ostringstream os;
    os << "sph transfer: min_weight_ratio = " << min_weight_ratio << " must be finite and >= 0";
    throw InvalidArgument(os.str());
  }
  switch (normalisation) {
    case SphNormalisation::None:
    case SphNormalisation::SumToOneLegacy:
    case SphNormalisation::Shepard: break;
    default: throw InvalidArgument("sph transfer: unknown normalisation mode");
  }
}

namespace {
SphGridDef one_channel(SphGridDef g) {
  g.channels = 1;
  return g;
}
const SphTransferDef& validated(const SphTransferDef& def) {
  def.validate();
  return def;
}
}  // namespace

SphTransfer::SphTransfer(const SphTransferDef& def)
    : def_(validated(def)),
      kernel_(def.kernel, def.support),
      grid_(def.grid),
      weights_(one_channel(def.grid)) {}

const SphGrid& SphTransfer::splat(std::span<const Vec2> points, std::span<const double> values) {
  // The weight field is always produced: it is cheap next to the C value channels and it
  // lets callers inspect the particle density whatever the mode.
  stats_ = splat_to_grid(kernel_, points, values, grid_, &weights_,
                         def_.normalisation == SphNormalisation::SumToOneLegacy);
  return grid_;
}

std::span<const double> SphTransfer::read_back(const SphGrid& grid, std::span<const Vec2> points) {
  const std::size_t n = points.size() * static_cast<std::size_t>(grid.channels());
  out_.resize(n);  // no reallocation once the capacity covers the largest call
  flags_.resize(points.size());
  std::span<double> out(out_.data(), n);
  std::span<std::uint8_t> flags(flags_.data(), points.size());
  if (def_.normalisation == SphNormalisation::Shepard) {
    unsupported_count_ = gather_shepard(grid, weights_, points, out, flags,
                                        def_.min_weight_ratio * kernel_.peak());
  } else {
    gather_bilinear(grid, points, out);
    std::fill(flags.begin(), flags.end(), std::uint8_t{0});
    unsupported_count_ = 0;
  }
  flags_view_ = flags;
  return out;
}

std::span<const double> SphTransfer::gather(const SphGrid& grid, std::span<const Vec2> points) {
  if (grid.nx() != grid_.nx() || grid.ny() != grid_.ny() || grid.spacing() != grid_.spacing()) {
    std::ostringstream os;
    os << "sph transfer: gather from a " << grid.nx() << "x" << grid.ny() << " grid (d = "
       << grid.spacing() << "), this transfer is " << grid_.nx() << "x" << grid_.ny()
       << " (d = " << grid_.spacing() << ")";
    throw InvalidArgument(os.str());
  }
  if (def_.normalisation == SphNormalisation::Shepard) splat_weights(kernel_, points, weights_);
  return read_back(grid, points);
}

std::span<const double> SphTransfer::round_trip(std::span<const Vec2> points,
                                                std::span<const double> values) {
  splat(points, values);
  return read_back(grid_, points);
}

}  // namespace dc
