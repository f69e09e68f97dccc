#pragma once
// The two halves of the SPH transfer as free functions over caller-owned grids (SphTransfer
// bundles them with buffers and a normalisation mode; docs/sph.md "Splatting").
//   G(c, node) = Σ_k W(|x_node − q_k|, h) · v_{k,c}   (1/m² · unit of v)
//   S(node)    = Σ_k W(|x_node − q_k|, h)             (kernel-weight field, 1/m²)
// S depends on the particle positions only, so for contacts it is known ahead of the solve.
// Each particle visits only the node box [⌈(q − h)/d⌉, ⌊(q + h)/d⌋] per axis (clipped):
// O(particles · (h/d)²), independent of the grid size apart from zeroing it. Read-back:
// bilinear (SphGrid::stencil), optionally divided by bilinear(S) (Shepard), which returns an
// isolated particle's value exactly. Values are particle-major, values[k·C + c].
#include <cstddef>
#include <cstdint>
#include <span>

#include "dc/core/vec2.hpp"
#include "dc/sph/sph_grid.hpp"
#include "dc/sph/sph_kernel.hpp"

namespace dc {

/// What a splat did (for tests of the neighbour search and for diagnostics).
struct SplatStats {
  std::size_t particles = 0;        ///< particles splatted
  std::size_t nodes_visited = 0;    ///< node-particle pairs examined (index boxes)
  std::size_t nodes_in_support = 0; ///< pairs with |x_node − q| < h (W > 0) that were written
  /// Particles with no node strictly within h: their value never reaches the grid and no
  /// read-back can recover it (happens when h < d·√2/2, or far outside the box).
  std::size_t particles_without_support = 0;
  /// The node rows the splat may have written: [row_lo, row_hi] (the union of the particles'
  /// index boxes; empty, row_lo > row_hi, when no particle reaches the grid).
  int row_lo = 0, row_hi = -1;
};

/// Splats `values` (particle-major, points.size() × grid.channels()) at `points` into
/// `grid`, overwriting it. When `weights` is non-null (one channel, same nx, ny, d as
/// `grid`) it is overwritten with the kernel-weight field S.
///
/// `renormalise_per_particle` is the legacy sum-to-one mode (docs/sph.md "The legacy modes"):
/// each particle's weights over the nodes it touches are divided by their sum ahead of
/// splatting (so Σ_nodes w = 1 per particle); `weights` then receives those renormalised
/// weights. With plain bilinear read-back this loses most of the value (docs/sph.md).
///
/// Throws InvalidArgument on size mismatches or non-finite points/values.
SplatStats splat_to_grid(const SphKernel& kernel, std::span<const Vec2> points,
                         std::span<const double> values, SphGrid& grid,
                         SphGrid* weights = nullptr, bool renormalise_per_particle = false);

/// splat_to_grid (no renormalisation) into a `grid` (and `weights`) that is already zero
/// outside the node rows [clear_lo, clear_hi] — e.g. zero-initialised, or holding a former
/// splat whose SplatStats row range lies there: only those rows are zeroed before the splat,
/// the same values as splat_to_grid without zeroing the rows it never reaches (the grid is
/// then zero outside the returned row range). The caller guarantees the zeros.
SplatStats splat_to_grid_rows(const SphKernel& kernel, std::span<const Vec2> points, std::span<const double> values,
                              SphGrid& grid, SphGrid* weights, int clear_lo, int clear_hi);
/// Only the kernel-weight field S of `points` (positions only) into the one-channel grid
/// `weights`, overwriting it.
SplatStats splat_weights(const SphKernel& kernel, std::span<const Vec2> points, SphGrid& weights);

/// Plain bilinear read-back: out[k·C + c] = bilinear(grid, c)(points[k]) (clamped to the box).
/// `out` must hold points.size() × grid.channels() values.
void gather_bilinear(const SphGrid& grid, std::span<const Vec2> points, std::span<double> out);

/// Shepard read-back: out[k·C + c] = bilinear(grid, c)(q_k) / bilinear(weights)(q_k).
/// Where the interpolated weight is ≤ min_weight (no kernel support at q's cell: the
/// ratio would be 0/0) the point gets 0 in every channel and unsupported[k] = 1, else
/// unsupported[k] = 0. Returns the number of unsupported points. `weights` must have one
/// channel and the geometry of `grid`; `unsupported` must hold points.size() entries.
std::size_t gather_shepard(const SphGrid& grid, const SphGrid& weights,
                           std::span<const Vec2> points, std::span<double> out,
                           std::span<std::uint8_t> unsupported, double min_weight);
/// The same with the points' stencils computed by the caller (grid.stencil(points[k]), e.g.
/// already at hand for listing the nodes they read): the same values bit for bit. Throws
/// InvalidArgument for a stencil whose nodes lie outside the grid.
std::size_t gather_shepard(const SphGrid& grid, const SphGrid& weights, std::span<const BilinearStencil> stencils,
                           std::span<double> out, std::span<std::uint8_t> unsupported, double min_weight);

}  // namespace dc
