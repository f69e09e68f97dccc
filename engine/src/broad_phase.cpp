#include "dc/engine/broad_phase.hpp"

#include <algorithm>
#include <cmath>

#include "dc/engine/error.hpp"

namespace dc {

void UniformGridBroadPhase::find_pairs(const std::vector<Vec2>& centres,
                                       const std::vector<double>& reach,
                                       std::vector<std::pair<int, int>>& pairs) {
  pairs.clear();
  pair_tests_ = 0;
  const int n = static_cast<int>(centres.size());
  if (n < 2) return;
  if (static_cast<int>(reach.size()) != n)
    throw InvalidArgument("UniformGridBroadPhase: reach must have one entry per body");
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(centres[k].x) || !std::isfinite(centres[k].y) || !std::isfinite(reach[k]))
      throw InvalidArgument("UniformGridBroadPhase: body " + std::to_string(k) +
                            " has a non-finite position or radius");
  find(
      n, [&](int k) { return Vec2{centres[k].x - reach[k], centres[k].y - reach[k]}; },
      [&](int k) { return Vec2{centres[k].x + reach[k], centres[k].y + reach[k]}; },
      [&](int k) { return 2 * reach[k]; }, pairs);
}

void UniformGridBroadPhase::find_box_pairs(const std::vector<Vec2>& lo, const std::vector<Vec2>& hi,
                                           std::vector<std::pair<int, int>>& pairs) {
  pairs.clear();
  pair_tests_ = 0;
  const int n = static_cast<int>(lo.size());
  if (n < 2) return;
  if (static_cast<int>(hi.size()) != n)
    throw InvalidArgument("UniformGridBroadPhase: need one upper corner per box");
  for (int k = 0; k < n; ++k)
    if (!std::isfinite(lo[k].x) || !std::isfinite(lo[k].y) || !std::isfinite(hi[k].x) || !std::isfinite(hi[k].y))
      throw InvalidArgument("UniformGridBroadPhase: body " + std::to_string(k) + " has a non-finite bounding box");
  find(
      n, [&](int k) { return lo[k]; }, [&](int k) { return hi[k]; },
      [&](int k) { return std::max(hi[k].x - lo[k].x, hi[k].y - lo[k].y); }, pairs);
}

template <class Lo, class Hi, class Extent>
void UniformGridBroadPhase::find(int n, const Lo& lo, const Hi& hi, const Extent& extent,
                                 std::vector<std::pair<int, int>>& pairs) {
  // Grid extent: bounding box of all boxes; cell = largest box extent (≥ tiny > 0).
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY, cell = 0;
  for (int k = 0; k < n; ++k) {
    const Vec2 l = lo(k), h = hi(k);
    xmin = std::min(xmin, l.x);
    ymin = std::min(ymin, l.y);
    xmax = std::max(xmax, h.x);
    ymax = std::max(ymax, h.y);
    cell = std::max(cell, extent(k));
  }
  cell = std::max(cell, 1e-12 * std::max({1.0, xmax - xmin, ymax - ymin}));
  // Cap the number of cells at ~4n so memory stays linear even for sparse, spread scenes.
  double nxd = std::floor((xmax - xmin) / cell) + 1, nyd = std::floor((ymax - ymin) / cell) + 1;
  while (nxd * nyd > 4.0 * n + 16) {
    cell *= 2;
    nxd = std::floor((xmax - xmin) / cell) + 1;
    nyd = std::floor((ymax - ymin) / cell) + 1;
  }
  const long long nx = static_cast<long long>(nxd), ny = static_cast<long long>(nyd);
  auto cx = [&](double x) { return std::clamp<long long>(static_cast<long long>((x - xmin) / cell), 0, nx - 1); };
  auto cy = [&](double y) { return std::clamp<long long>(static_cast<long long>((y - ymin) / cell), 0, ny - 1); };

  // Counting sort of (cell, body) entries: a body enters every cell its box touches.
  cell_of_entry_.clear();
  body_cells_.clear();
  for (int k = 0; k < n; ++k) {
    const Vec2 l = lo(k), h = hi(k);
    const long long i0 = cx(l.x), i1 = cx(h.x);
    const long long j0 = cy(l.y), j1 = cy(h.y);
    for (long long j = j0; j <= j1; ++j)
      for (long long i = i0; i <= i1; ++i) {
        cell_of_entry_.push_back(j * nx + i);
        body_cells_.push_back(k);
      }
  }
  const long long ncell = nx * ny;
  cell_start_.assign(static_cast<size_t>(ncell + 1), 0);
  for (long long c : cell_of_entry_) ++cell_start_[static_cast<size_t>(c + 1)];
  for (long long c = 0; c < ncell; ++c) cell_start_[static_cast<size_t>(c + 1)] += cell_start_[static_cast<size_t>(c)];
  cell_items_.assign(cell_of_entry_.size(), 0);
  {
    std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (size_t e = 0; e < cell_of_entry_.size(); ++e)
      cell_items_[static_cast<size_t>(fill[static_cast<size_t>(cell_of_entry_[e])]++)] = body_cells_[e];
  }

  // Each overlapping pair is reported only from the cell holding the lower-left corner of
  // the intersection of the two boxes, so no de-duplication pass is needed.
  for (long long c = 0; c < ncell; ++c) {
    const int s = cell_start_[static_cast<size_t>(c)], e = cell_start_[static_cast<size_t>(c + 1)];
    for (int p = s; p < e; ++p) {
      const int a = cell_items_[static_cast<size_t>(p)];
      for (int q = p + 1; q < e; ++q) {
        const int b = cell_items_[static_cast<size_t>(q)];
        ++pair_tests_;
        const Vec2 la = lo(a), lb = lo(b), ha = hi(a), hb = hi(b);
        const double lx = std::max(la.x, lb.x);
        const double ly = std::max(la.y, lb.y);
        const double hx = std::min(ha.x, hb.x);
        const double hy = std::min(ha.y, hb.y);
        if (lx > hx || ly > hy) continue;
        if (cy(ly) * nx + cx(lx) != c) continue;
        pairs.emplace_back(std::min(a, b), std::max(a, b));
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
}

}  // namespace dc
