#pragma once
// SphTransfer: the particle → grid → particle round trip with one grid, one kernel and one
// normalisation mode, reusing its buffers across calls (no allocation in steady state:
// the grids are allocated once in the constructor, the output buffers grow to the largest
// point count seen and are then reused).
//
// Normalisation modes (docs/sph.md has the derivations and measured losses):
//
//   Shepard         splat G = Σ W v and S = Σ W; read back v̂(q) = bilinear(G)(q) / bilinear(S)(q).
//                   An isolated particle's value survives the round trip EXACTLY (up to
//                   rounding) for any kernel and any (d, h) for which some node of q's cell
//                   lies strictly within h (always when h > d·√2/2). Where bilinear(S)(q) ≤
//                   min_weight_ratio · W(0, h) the point is flagged unsupported and gets 0
//                   (never NaN). The kernel's constant cancels in the ratio.
//   None            plain: splat G = Σ W v, read back bilinear(G)(q). The value comes back
//                   scaled by ≈ W d²-sums, i.e. the grid is a density (1/m²) not a value.
//   SumToOneLegacy  the earlier theses' mode: each particle's weights renormalised to sum
//                   to 1 over the nodes it touches, plain bilinear back, no Shepard. An
//                   isolated particle returns only a fraction of its value (the share of
//                   its mass on the four corners of its cell, weighted bilinearly) — the
//                   docs/design.md §4 trap; kept to reproduce it, never the default.
//
// Gathering a grid that did not come from this object's last splat (e.g. a CNN-predicted
// label grid) in Shepard mode: the denominator S depends only on the query points'
// positions (the contact points, known before the solve), so gather() rebuilds S from
// the points it is given.
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
