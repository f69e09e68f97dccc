#include "dc/sph/sph_splat.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>

#include "dc/core/error.hpp"

namespace dc {

namespace {

[[noreturn]] void bad(const std::string& what) { throw InvalidArgument("sph transfer: " + what); }

void require_same_geometry(const SphGrid& a, const SphGrid& b, const char* name) {
  if (a.nx() != b.nx() || a.ny() != b.ny() || a.spacing() != b.spacing()) {
    std::ostringstream os;
    os << name << " grid is " << b.nx() << "x" << b.ny() << " (d = " << b.spacing()
       << "), the value grid " << a.nx() << "x" << a.ny() << " (d = " << a.spacing() << ")";
    bad(os.str());
  }
}

void require_finite_points(std::span<const Vec2> points) {
  for (std::size_t k = 0; k < points.size(); ++k)
    if (!std::isfinite(points[k].x) || !std::isfinite(points[k].y))
      bad("point " + std::to_string(k) + " has a non-finite coordinate");
}

// Node index range along one axis whose nodes may lie within h of coordinate q:
// [⌈(q − h)/d⌉, ⌊(q + h)/d⌋] ∩ [0, n−1]. Widened by 1e-9 nodes so rounding of the
// division never drops a node strictly inside the support; nodes at r ≥ h get W = 0 from
// the r² test anyway. Clamped in double first so far-away points cannot overflow int.
inline void node_range(double q, double h, double inv_d, int n, int& lo, int& hi) {
  double a = std::ceil((q - h) * inv_d - 1e-9);
  double b = std::floor((q + h) * inv_d + 1e-9);
  a = std::max(a, 0.0);
  b = std::min(b, static_cast<double>(n - 1));
  if (a > b) { lo = 0; hi = -1; return; }
  lo = static_cast<int>(a);
  hi = static_cast<int>(b);
}

// The kernels as functors of r² (called only for r² < h²), so that the splat loop is
// compiled once per kernel with the evaluation inlined — one dispatch per call.
struct Poly6 {
  double c, h2;
  double operator()(double r2) const { return detail::poly6_r2(c, h2, r2); }
};
struct Spiky {
  double c, h;
  double operator()(double r2) const { return detail::spiky_r2(c, h, r2); }
};
struct Cubic {
  double c, inv_h;
  double operator()(double r2) const { return detail::cubic_r2(c, inv_h, r2); }
};

// The splat loop. g: value grid data (C channels, may be null when C = 0); s: weight grid
// (may be null). v: particle-major values with C channels. CC ≥ 0: C known at compile time
// (= CC), so that the channel loop is unrolled; the same operations per element either way.
template <class Kernel, int CC>
SplatStats splat_loop(const Kernel& w, double h, double d, int nx, int ny,
                      std::span<const Vec2> points, const double* v, int C_, double* g,
                      double* s, bool renormalise) {
  const int C = CC >= 0 ? CC : C_;
  SplatStats st;
  st.particles = points.size();
  const double h2 = h * h;
  const double inv_d = 1.0 / d;
  const std::size_t plane = static_cast<std::size_t>(nx) * ny;
  int rows_lo = ny, rows_hi = -1;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vec2 q = points[k];
    int i_lo, i_hi, j_lo, j_hi;
    node_range(q.x, h, inv_d, nx, i_lo, i_hi);
    node_range(q.y, h, inv_d, ny, j_lo, j_hi);
    if (i_lo > i_hi || j_lo > j_hi) { ++st.particles_without_support; continue; }
    rows_lo = std::min(rows_lo, j_lo);
    rows_hi = std::max(rows_hi, j_hi);

    // Legacy sum-to-one: first pass for Σ_nodes W, then splat W / Σ W.
    double scale = 1.0;
    if (renormalise) {
      double sum = 0.0;
      for (int j = j_lo; j <= j_hi; ++j) {
        const double dy = j * d - q.y;
        for (int i = i_lo; i <= i_hi; ++i) {
          const double dx = i * d - q.x;
          const double r2 = dx * dx + dy * dy;
          if (r2 < h2) sum += w(r2);
        }
      }
      if (!(sum > 0.0)) {
        ++st.particles_without_support;
        st.nodes_visited += static_cast<std::size_t>(i_hi - i_lo + 1) * (j_hi - j_lo + 1);
        continue;
      }
      scale = 1.0 / sum;
    }

    const double* vk = v + k * static_cast<std::size_t>(C);
    std::size_t in_support = 0;
    for (int j = j_lo; j <= j_hi; ++j) {
      const double dy = j * d - q.y;
      const std::size_t row = static_cast<std::size_t>(j) * nx;
      for (int i = i_lo; i <= i_hi; ++i) {
        const double dx = i * d - q.x;
        const double r2 = dx * dx + dy * dy;
        if (!(r2 < h2)) continue;
        const double wt = renormalise ? w(r2) * scale : w(r2);
        const std::size_t node = row + i;
        for (int c = 0; c < C; ++c) g[c * plane + node] += wt * vk[c];
        if (s) s[node] += wt;
        ++in_support;
      }
    }
    st.nodes_visited += static_cast<std::size_t>(i_hi - i_lo + 1) * (j_hi - j_lo + 1);
    st.nodes_in_support += in_support;
    if (in_support == 0) ++st.particles_without_support;
  }
  if (rows_lo <= rows_hi) {
    st.row_lo = rows_lo;
    st.row_hi = rows_hi;
  }
  return st;
}

SplatStats dispatch(const SphKernel& kernel, const SphGrid& geometry,
                    std::span<const Vec2> points, const double* v, int C, double* g, double* s,
                    bool renormalise) {
  const double h = kernel.h();
  const double c = kernel.constant();
  const double d = geometry.spacing();
  const int nx = geometry.nx();
  const int ny = geometry.ny();
  // The channel counts of the feature image's splats (weights only, normals or labels, body
  // fields, per-contact values) compiled with C fixed; others with C at run time.
  const auto channels = [&](const auto& w) {
    using K = std::decay_t<decltype(w)>;
    switch (C) {
      case 0: return splat_loop<K, 0>(w, h, d, nx, ny, points, v, C, g, s, renormalise);
      case 2: return splat_loop<K, 2>(w, h, d, nx, ny, points, v, C, g, s, renormalise);
      case 4: return splat_loop<K, 4>(w, h, d, nx, ny, points, v, C, g, s, renormalise);
      case 5: return splat_loop<K, 5>(w, h, d, nx, ny, points, v, C, g, s, renormalise);
      default: return splat_loop<K, -1>(w, h, d, nx, ny, points, v, C, g, s, renormalise);
    }
  };
  switch (kernel.type()) {
    case SphKernelType::Poly6:
    case SphKernelType::Poly6Legacy3d:
      return channels(Poly6{c, h * h});
    case SphKernelType::Spiky:
    case SphKernelType::SpikyLegacy3d:
      return channels(Spiky{c, h});
    case SphKernelType::Cubic:
      return channels(Cubic{c, 1.0 / h});
  }
  bad("unknown kernel type");
}

// The checks of splat_to_grid: sizes, geometry, finite points and values.
void require_splat_inputs(std::span<const Vec2> points, std::span<const double> values, const SphGrid& grid,
                          const SphGrid* weights) {
  const int C = grid.channels();
  if (grid.nodes() == 0) bad("splat into an empty grid");
  if (values.size() != points.size() * static_cast<std::size_t>(C)) {
    std::ostringstream os;
    os << "splat: " << values.size() << " values for " << points.size() << " points x " << C
       << " channels (expected " << points.size() * static_cast<std::size_t>(C) << ")";
    bad(os.str());
  }
  if (weights) {
    require_same_geometry(grid, *weights, "weight");
    if (weights->channels() != 1) bad("weight grid must have exactly one channel");
  }
  require_finite_points(points);
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!std::isfinite(values[k]))
      bad("value of point " + std::to_string(k / C) + ", channel " + std::to_string(k % C) +
          " is not finite");
}

// Zeroes node rows [lo, hi] (clamped) of every channel of g.
void zero_rows(SphGrid& g, int lo, int hi) {
  lo = std::max(lo, 0);
  hi = std::min(hi, g.ny() - 1);
  if (lo > hi) return;
  for (int c = 0; c < g.channels(); ++c) {
    const auto first = g.channel(c).begin() + static_cast<std::ptrdiff_t>(lo) * g.nx();
    std::fill(first, first + static_cast<std::ptrdiff_t>(hi - lo + 1) * g.nx(), 0.0);
  }
}

}  // namespace

SplatStats splat_to_grid(const SphKernel& kernel, std::span<const Vec2> points,
                         std::span<const double> values, SphGrid& grid, SphGrid* weights,
                         bool renormalise_per_particle) {
  require_splat_inputs(points, values, grid, weights);
  grid.fill(0.0);
  if (weights) weights->fill(0.0);
  return dispatch(kernel, grid, points, values.data(), grid.channels(), grid.data().data(),
                  weights ? weights->data().data() : nullptr, renormalise_per_particle);
}

SplatStats splat_to_grid_rows(const SphKernel& kernel, std::span<const Vec2> points, std::span<const double> values,
                              SphGrid& grid, SphGrid* weights, int clear_lo, int clear_hi) {
  require_splat_inputs(points, values, grid, weights);
  zero_rows(grid, clear_lo, clear_hi);
  if (weights) zero_rows(*weights, clear_lo, clear_hi);
  return dispatch(kernel, grid, points, values.data(), grid.channels(), grid.data().data(),
                  weights ? weights->data().data() : nullptr, false);
}

SplatStats splat_weights(const SphKernel& kernel, std::span<const Vec2> points, SphGrid& weights) {
  if (weights.nodes() == 0) bad("splat into an empty grid");
  if (weights.channels() != 1) bad("weight grid must have exactly one channel");
  require_finite_points(points);
  weights.fill(0.0);
  return dispatch(kernel, weights, points, nullptr, 0, nullptr, weights.data().data(), false);
}

void gather_bilinear(const SphGrid& grid, std::span<const Vec2> points, std::span<double> out) {
  const int C = grid.channels();
  if (grid.nodes() == 0) bad("gather from an empty grid");
  if (out.size() != points.size() * static_cast<std::size_t>(C))
    bad("gather: output holds " + std::to_string(out.size()) + " values, expected " +
        std::to_string(points.size() * static_cast<std::size_t>(C)));
  for (std::size_t k = 0; k < points.size(); ++k) {
    const BilinearStencil st = grid.stencil(points[k]);
    for (int c = 0; c < C; ++c) out[k * C + c] = grid.apply(c, st);
  }
}

namespace {

// gather_shepard's checks and loop; stencil(k) gives point k's bilinear stencil.
template <class Stencil>
std::size_t shepard_loop(const SphGrid& grid, const SphGrid& weights, std::size_t n, Stencil stencil,
                         std::span<double> out, std::span<std::uint8_t> unsupported, double min_weight) {
  const int C = grid.channels();
  if (grid.nodes() == 0) bad("gather from an empty grid");
  require_same_geometry(grid, weights, "weight");
  if (weights.channels() != 1) bad("weight grid must have exactly one channel");
  if (out.size() != n * static_cast<std::size_t>(C))
    bad("gather: output holds " + std::to_string(out.size()) + " values, expected " +
        std::to_string(n * static_cast<std::size_t>(C)));
  if (unsupported.size() != n)
    bad("gather: flag buffer holds " + std::to_string(unsupported.size()) + " entries for " +
        std::to_string(n) + " points");
  if (!(min_weight >= 0.0)) bad("gather: min_weight must be >= 0");
  std::size_t missing = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const BilinearStencil st = stencil(k);
    const double sw = weights.apply(0, st);
    if (!(sw > min_weight)) {
      for (int c = 0; c < C; ++c) out[k * C + c] = 0.0;
      unsupported[k] = 1;
      ++missing;
      continue;
    }
    unsupported[k] = 0;
    for (int c = 0; c < C; ++c) out[k * C + c] = grid.apply(c, st) / sw;
  }
  return missing;
}

}  // namespace

std::size_t gather_shepard(const SphGrid& grid, const SphGrid& weights,
                           std::span<const Vec2> points, std::span<double> out,
                           std::span<std::uint8_t> unsupported, double min_weight) {
  return shepard_loop(grid, weights, points.size(), [&](std::size_t k) { return grid.stencil(points[k]); }, out,
                      unsupported, min_weight);
}

std::size_t gather_shepard(const SphGrid& grid, const SphGrid& weights, std::span<const BilinearStencil> stencils,
                           std::span<double> out, std::span<std::uint8_t> unsupported, double min_weight) {
  for (const BilinearStencil& st : stencils)
    if (st.i0 < 0 || st.i1 >= std::max(grid.nx(), 1) || st.i1 < st.i0 || st.j0 < 0 || st.j1 >= std::max(grid.ny(), 1) ||
        st.j1 < st.j0)
      bad("gather: a stencil's nodes lie outside the grid");
  return shepard_loop(grid, weights, stencils.size(), [&](std::size_t k) { return stencils[k]; }, out, unsupported,
                      min_weight);
}

}  // namespace dc
