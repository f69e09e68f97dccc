#pragma once
// SphTransfer: the particle → grid → particle round trip with one grid, one kernel and one
// normalisation mode, reusing its buffers (no allocation in steady state). Modes (docs/sph.md
// "Normalisation modes and the round-trip guarantee"):
//   Shepard         G = Σ W v, S = Σ W; v̂(q) = bilinear(G)(q) / bilinear(S)(q): an isolated
//                   particle's value survives exactly (up to rounding) when some node of q's
//                   cell lies strictly within h (always when h > d·√2/2); where bilinear(S)(q)
//                   ≤ min_weight_ratio · W(0, h) the point is unsupported and gets 0, never NaN.
//   None            G = Σ W v read back as bilinear(G)(q): the grid is a density (1/m²).
//   SumToOneLegacy  weights renormalised to sum to 1 per particle, plain bilinear back: loses
//                   most of an isolated value (docs/design.md §4); never the default.
// Shepard's S depends only on the query points, so gather() of a grid from elsewhere (a
// predicted label grid) rebuilds S from the points it is given.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "dc/core/vec2.hpp"
#include "dc/sph/sph_grid.hpp"
#include "dc/sph/sph_kernel.hpp"
#include "dc/sph/sph_splat.hpp"

namespace dc {

enum class SphNormalisation {
  None,            ///< "none": raw kernel sums, plain bilinear back
  SumToOneLegacy,  ///< "sum-to-one-legacy": per-particle weights sum to 1, plain bilinear back
  Shepard,         ///< "shepard": bilinear(G) / bilinear(S) — the default
};

/// "none", "sum-to-one-legacy", "shepard".
const char* to_string(SphNormalisation mode);
/// Inverse of to_string (also accepts "legacy" for sum-to-one-legacy); ConfigError otherwise.
SphNormalisation parse_sph_normalisation(std::string_view name);

/// Parameters of a transfer. Defaults: the seed's poly6 with h = d = 0.5 on the 61 × 61
/// grid of the 30 × 30 box, two channels (λ_n, λ_t), Shepard read-back.
struct SphTransferDef {
  SphGridDef grid;                               ///< box, spacing d, channels C
  SphKernelType kernel = SphKernelType::Poly6;   ///< W
  double support = 0.5;                          ///< kernel support radius h [m]
  SphNormalisation normalisation = SphNormalisation::Shepard;
  /// Shepard guard: a point whose interpolated weight bilinear(S)(q) ≤ ratio · W(0, h) has
  /// no kernel support (the quotient would be 0/0) and reads 0, flagged. Must be ≥ 0.
  double min_weight_ratio = 1e-12;
  /// Throws InvalidArgument naming the offending field.
  void validate() const;
};

class SphTransfer {
 public:
  /// Validates `def` and allocates the value grid (C channels) and the weight grid.
  explicit SphTransfer(const SphTransferDef& def);

  [[nodiscard]] const SphTransferDef& def() const { return def_; }
  [[nodiscard]] const SphKernel& kernel() const { return kernel_; }
  [[nodiscard]] int channels() const { return grid_.channels(); }

  /// Particle → grid: values are particle-major (values[k·C + c]), C = def().grid.channels.
  /// In SumToOneLegacy mode the per-particle renormalised weights are splatted. Also fills
  /// weights() with S (renormalised weights in legacy mode). Returns grid(), valid until the
  /// next call.
  const SphGrid& splat(std::span<const Vec2> points, std::span<const double> values);

  /// Grid → particles: out[k·C + c] for the C channels of `grid` (which must have this
  /// transfer's nx, ny, d). None/SumToOneLegacy: plain bilinear. Shepard: bilinear(grid)
  /// divided by bilinear(S) where S is rebuilt from `points` (overwrites weights()).
  /// The span is valid until the next call.
  std::span<const double> gather(const SphGrid& grid, std::span<const Vec2> points);

  /// splat(points, values) then the read-back of the mode at the same points (Shepard
  /// reuses the S of the splat). Returns values in the layout of the input.
  std::span<const double> round_trip(std::span<const Vec2> points, std::span<const double> values);

  /// The value grid and weight grid of the last splat (or of gather's S rebuild).
  [[nodiscard]] const SphGrid& grid() const { return grid_; }
  [[nodiscard]] const SphGrid& weights() const { return weights_; }
  /// Statistics of the last splat.
  [[nodiscard]] const SplatStats& last_splat() const { return stats_; }
  /// Per point of the last gather/round trip: 1 where Shepard found no support (value 0).
  /// Always 0 in the None and SumToOneLegacy modes (see last_splat() for lost particles).
  [[nodiscard]] std::span<const std::uint8_t> unsupported() const { return flags_view_; }
  [[nodiscard]] std::size_t unsupported_count() const { return unsupported_count_; }

 private:
  std::span<const double> read_back(const SphGrid& grid, std::span<const Vec2> points);

  SphTransferDef def_;
  SphKernel kernel_;
  SphGrid grid_;
  SphGrid weights_;
  SplatStats stats_;
  std::vector<double> out_;
  std::vector<std::uint8_t> flags_;
  std::span<const std::uint8_t> flags_view_;
  std::size_t unsupported_count_ = 0;
};

}  // namespace dc
