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

  // Grid extent: bounding box of all boxes; cell = largest box extent (≥ tiny > 0).
  double xmin = INFINITY, ymin = INFINITY, xmax = -INFINITY, ymax = -INFINITY, cell = 0;
  for (int k = 0; k < n; ++k) {
    const double r = reach[k];
    if (!std::isfinite(centres[k].x) || !std::isfinite(centres[k].y) || !std::isfinite(r))
      throw InvalidArgument("UniformGridBroadPhase: body " + std::to_string(k) +
                            " has a non-finite position or radius");
    xmin = std::min(xmin, centres[k].x - r);
    ymin = std::min(ymin, centres[k].y - r);
    xmax = std::max(xmax, centres[k].x + r);
    ymax = std::max(ymax, centres[k].y + r);
    cell = std::max(cell, 2 * r);
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
    const long long i0 = cx(centres[k].x - reach[k]), i1 = cx(centres[k].x + reach[k]);
    const long long j0 = cy(centres[k].y - reach[k]), j1 = cy(centres[k].y + reach[k]);
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
        const double ra = reach[a], rb = reach[b];
        const double lx = std::max(centres[a].x - ra, centres[b].x - rb);
        const double ly = std::max(centres[a].y - ra, centres[b].y - rb);
        const double hx = std::min(centres[a].x + ra, centres[b].x + rb);
        const double hy = std::min(centres[a].y + ra, centres[b].y + rb);
        if (lx > hx || ly > hy) continue;
        if (cy(ly) * nx + cx(lx) != c) continue;
        pairs.emplace_back(std::min(a, b), std::max(a, b));
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
}

}  // namespace dc
