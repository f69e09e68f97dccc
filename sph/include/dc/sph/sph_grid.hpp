#pragma once
// A regular multi-channel grid over the simulation box [0, W] × [0, H] (docs/design.md §4,
// docs/sph.md "Grid layout and orientation"). Nodes x_i = i·d, i < nx = floor(W/d + 1e-9) + 1
// (the 1e-9 absorbs the rounding of W/d), likewise y_j; when W is not a multiple of d the last
// node lies short of the wall. Storage: one std::vector<double>, value(c, j, i) at
// (c·ny + j)·nx + i — NCHW with H = ny, W = nx; row j = 0 is y = 0, the bottom of the box (no
// flip: plot with origin="lower"). Grid → point: bilinear with u = x/d, v = y/d, i0 = ⌊u⌋,
// j0 = ⌊v⌋, fx = u − i0, fy = v − j0:
//   f = (1−fy)[(1−fx) f(j0, i0) + fx f(j0, i0+1)] + fy[(1−fx) f(j0+1, i0) + fx f(j0+1, i0+1)]
// Points are clamped to the node rectangle first, so a point on or beyond a wall reads the
// border value instead of reading outside the array.
#include <cstddef>
#include <span>
#include <vector>

#include "dc/core/vec2.hpp"

namespace dc {

/// Parameters of a grid. Defaults: the seed's 30 × 30 box, d = 0.5, two channels (λ_n, λ_t).
struct SphGridDef {
  double width = 30.0;   ///< box extent along x [m]
  double height = 30.0;  ///< box extent along y [m]
  double spacing = 0.5;  ///< node spacing d [m]
  int channels = 2;      ///< number of channels C (≥ 1)

  /// Largest accepted node count per axis; finer grids are configuration mistakes.
  static constexpr int kMaxNodesPerAxis = 4096;
  /// Largest accepted number of channels.
  static constexpr int kMaxChannels = 1024;
  /// Throws InvalidArgument naming the offending field: non-finite or non-positive extent
  /// or spacing, channels outside [1, kMaxChannels], more than kMaxNodesPerAxis nodes on
  /// an axis, or more than 2²⁸ values in all.
  void validate() const;
};

/// Nodes along an axis of the given extent: floor(extent/d + 1e-9) + 1 (no validation).
int sph_node_count(double extent, double spacing);

/// Where a point falls in the grid: lower-left node (i0, j0), the node one further along
/// each axis (i1, j1; equal to i0/j0 on a one-node axis) and the fractions fx, fy ∈ [0, 1].
struct BilinearStencil {
  int i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  double fx = 0.0, fy = 0.0;
  /// The four weights of nodes (j0,i0), (j0,i1), (j1,i0), (j1,i1); they sum to 1.
  [[nodiscard]] double w00() const { return (1.0 - fy) * (1.0 - fx); }
  [[nodiscard]] double w01() const { return (1.0 - fy) * fx; }
  [[nodiscard]] double w10() const { return fy * (1.0 - fx); }
  [[nodiscard]] double w11() const { return fy * fx; }
};

class SphGrid {
 public:
  /// An empty 0 × 0 grid (assign a real one before use).
  SphGrid() = default;
  /// Validates `def` and allocates a zeroed grid.
  explicit SphGrid(const SphGridDef& def);

  [[nodiscard]] const SphGridDef& def() const { return def_; }
  [[nodiscard]] int nx() const { return nx_; }                 ///< nodes along x (columns)
  [[nodiscard]] int ny() const { return ny_; }                 ///< nodes along y (rows)
  [[nodiscard]] int channels() const { return def_.channels; }  ///< C
  [[nodiscard]] double spacing() const { return def_.spacing; } ///< d [m]
  [[nodiscard]] std::size_t nodes() const { return static_cast<std::size_t>(nx_) * ny_; }
  [[nodiscard]] std::size_t size() const { return data_.size(); }  ///< C·ny·nx

  /// Flat index of value(c, j, i) = (c·ny + j)·nx + i (no bounds check).
  [[nodiscard]] std::size_t index(int c, int j, int i) const {
    return (static_cast<std::size_t>(c) * ny_ + j) * nx_ + i;
  }
  /// Value of channel c at row j (y = j·d), column i (x = i·d); no bounds check.
  [[nodiscard]] double& at(int c, int j, int i) { return data_[index(c, j, i)]; }
  [[nodiscard]] double at(int c, int j, int i) const { return data_[index(c, j, i)]; }
  /// Node position (x_i, y_j) = (i·d, j·d) [m].
  [[nodiscard]] Vec2 node(int i, int j) const { return {i * def_.spacing, j * def_.spacing}; }

  [[nodiscard]] std::span<double> data() { return data_; }
  [[nodiscard]] std::span<const double> data() const { return data_; }
  /// The ny·nx values of channel c (row-major image).
  [[nodiscard]] std::span<double> channel(int c);
  [[nodiscard]] std::span<const double> channel(int c) const;

  /// Sets every value to v (no reallocation).
  void fill(double v);

  /// The stencil of point p after clamping p to the node rectangle (see the file comment).
  /// NaN coordinates are treated as 0 (the caller validates its points).
  [[nodiscard]] BilinearStencil stencil(Vec2 p) const;
  /// Bilinear value of channel c at p (clamped); c must be in [0, channels).
  [[nodiscard]] double bilinear(int c, Vec2 p) const { return apply(c, stencil(p)); }
  /// Bilinear value of channel c for a precomputed stencil.
  [[nodiscard]] double apply(int c, const BilinearStencil& s) const {
    const double* ch = data_.data() + static_cast<std::size_t>(c) * nodes();
    const double* r0 = ch + static_cast<std::size_t>(s.j0) * nx_;
    const double* r1 = ch + static_cast<std::size_t>(s.j1) * nx_;
    return (1.0 - s.fy) * ((1.0 - s.fx) * r0[s.i0] + s.fx * r0[s.i1]) +
           s.fy * ((1.0 - s.fx) * r1[s.i0] + s.fx * r1[s.i1]);
  }

 private:
  SphGridDef def_{0.0, 0.0, 1.0, 0};
  int nx_ = 0;
  int ny_ = 0;
  std::vector<double> data_;
};

}  // namespace dc
