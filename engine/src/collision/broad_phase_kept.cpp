// The broad phase's kept candidates between calls (broad_phase.hpp): the escaped bodies' queries
// of the kept grid of fat boxes, and the filter of the candidates by the true boxes.
#include <algorithm>
#include <cmath>

#include "dc/engine/broad_phase.hpp"
#include "world/parts/step_parts.hpp"

namespace dc {

long long UniformGridBroadPhase::kept_cell(double x, double y) const {
  // find()'s cell index, clamped before the conversion: a box that left the grid's bounds far
  // behind lands in an edge cell (the clamp is monotone, so neighbours stay neighbours).
  const double inv_cell = 1.0 / grid_cell_;
  const double i = std::clamp((x - grid_x0_) * inv_cell, 0.0, static_cast<double>(grid_nx_ - 1));
  const double j = std::clamp((y - grid_y0_) * inv_cell, 0.0, static_cast<double>(grid_ny_ - 1));
  return static_cast<long long>(j) * grid_nx_ + static_cast<long long>(i);
}

bool UniformGridBroadPhase::requery_escaped() {
  // A query finds the partners of a fat box among the 3 × 3 cells around its lower corner's
  // cell, which needs the box's extent within the cell (as at the rebuild: cell ≥ extent·(1 +
  // 1e-9), so rounding cannot put two overlapping corners two cells apart).
  const double m = margin_;
  for (const int k : escaped_) {
    const double* t = tbox_.data() + 4 * static_cast<size_t>(k);
    const double extent = std::max(t[2] - t[0], t[3] - t[1]) + 2 * m;
    if (!(extent * (1 + 1e-9) <= grid_cell_)) return false;
  }
  // New fat boxes, each body moved to its new cell.
  for (const int k : escaped_) {
    const auto i = static_cast<size_t>(k);
    is_escaped_[i] = 1;
    const double* t = tbox_.data() + 4 * i;
    double* f = fbox_.data() + 4 * i;
    f[0] = t[0] - m, f[1] = t[1] - m, f[2] = t[2] + m, f[3] = t[3] + m;
    const long long c = kept_cell(f[0], f[1]);
    if (c == kept_cell_of_[i]) continue;
    const int before = prev_[i], after = next_[i];
    (before >= 0 ? next_[static_cast<size_t>(before)] : head_[static_cast<size_t>(kept_cell_of_[i])]) = after;
    if (after >= 0) prev_[static_cast<size_t>(after)] = before;
    const int first = head_[static_cast<size_t>(c)];
    next_[i] = first;
    prev_[i] = -1;
    if (first >= 0) prev_[static_cast<size_t>(first)] = k;
    head_[static_cast<size_t>(c)] = k;
    kept_cell_of_[i] = c;
  }
  // Their pairs: each escaped body against every body in the 3 × 3 cells (a pair of two escaped
  // bodies once, from its smaller body: the neighbourhood is symmetric).
  requeried_.clear();
  std::size_t tests = 0;
  for (const int k : escaped_) {
    const auto i = static_cast<size_t>(k);
    const double* a = fbox_.data() + 4 * i;
    const long long c = kept_cell_of_[i], cx = c % grid_nx_, cy = c / grid_nx_;
    for (long long y = std::max(0LL, cy - 1); y <= std::min(grid_ny_ - 1, cy + 1); ++y)
      for (long long x = std::max(0LL, cx - 1); x <= std::min(grid_nx_ - 1, cx + 1); ++x)
        for (int j = head_[static_cast<size_t>(y * grid_nx_ + x)]; j >= 0; j = next_[static_cast<size_t>(j)]) {
          if (j == k || (j < k && is_escaped_[static_cast<size_t>(j)])) continue;
          ++tests;
          const double* b = fbox_.data() + 4 * static_cast<size_t>(j);
          if (std::max(a[0], b[0]) > std::min(a[2], b[2]) || std::max(a[1], b[1]) > std::min(a[3], b[3])) continue;
          requeried_.emplace_back(std::min(k, j), std::max(k, j));
        }
  }
  std::sort(requeried_.begin(), requeried_.end());
  // C without the escaped bodies' old pairs, merged with their new ones (both sorted).
  cand_next_.clear();
  if (cand_next_.capacity() < cand_.size() + requeried_.size())
    cand_next_.reserve((cand_.size() + requeried_.size()) * 5 / 4);
  auto fresh = requeried_.begin();
  for (const std::pair<int, int>& q : cand_) {
    if (is_escaped_[static_cast<size_t>(q.first)] | is_escaped_[static_cast<size_t>(q.second)]) continue;
    for (; fresh != requeried_.end() && *fresh < q; ++fresh) cand_next_.push_back(*fresh);
    cand_next_.push_back(q);
  }
  cand_next_.insert(cand_next_.end(), fresh, requeried_.end());
  cand_.swap(cand_next_);
  for (const int k : escaped_) is_escaped_[static_cast<size_t>(k)] = 0;
  pair_tests_ += tests;
  return true;
}

std::size_t UniformGridBroadPhase::filter_candidates(std::vector<std::pair<int, int>>& pairs, int threads) {
  // The test of a fresh search (test_rows) on the same true boxes, the outcome added rather than
  // branched on; by jobs of ranges of C, each into its own list, then copied in job order.
  const long nc = static_cast<long>(cand_.size());
  const int jobs = parts_for(threads, nc, 2, 16384);
  if (part_pairs_.size() < static_cast<size_t>(jobs)) part_pairs_.resize(static_cast<size_t>(jobs));
  const double* t = tbox_.data();
  const std::pair<int, int>* c = cand_.data();
  auto filter = [&](long q0, long q1, std::pair<int, int>* dst) {
    std::size_t found = 0;
    for (long q = q0; q < q1; ++q) {
      const std::pair<int, int> pq = c[q];
      const double* a = t + 4 * static_cast<size_t>(pq.first);
      const double* b = t + 4 * static_cast<size_t>(pq.second);
      const bool apart_x = std::max(a[0], b[0]) > std::min(a[2], b[2]);
      const bool apart_y = std::max(a[1], b[1]) > std::min(a[3], b[3]);
      dst[found] = pq;
      found += static_cast<std::size_t>(!(apart_x | apart_y));
    }
    return found;
  };
  if (pairs.capacity() < cand_.size()) pairs.reserve(cand_.size() + cand_.size() / 4);
  if (jobs == 1) {
    pairs.resize(cand_.size());
    pairs.resize(filter(0, nc, pairs.data()));
    return cand_.size();
  }
  found_.assign(static_cast<size_t>(jobs), 0);
  run_parts(threads, jobs, [&](int p) {
    std::vector<std::pair<int, int>>& list = part_pairs_[static_cast<size_t>(p)];
    const long q0 = part_begin(nc, jobs, p), q1 = part_begin(nc, jobs, p + 1);
    if (list.size() < static_cast<size_t>(q1 - q0)) list.resize(static_cast<size_t>(q1 - q0));
    found_[static_cast<size_t>(p)] = filter(q0, q1, list.data());
  });
  std::size_t total = 0;
  for (const std::size_t f : found_) total += f;
  pairs.resize(total);
  std::size_t at = 0;
  for (int p = 0; p < jobs; ++p) {
    const auto& list = part_pairs_[static_cast<size_t>(p)];
    std::copy(list.begin(), list.begin() + static_cast<std::ptrdiff_t>(found_[static_cast<size_t>(p)]), pairs.begin() + static_cast<std::ptrdiff_t>(at));
    at += found_[static_cast<size_t>(p)];
  }
  return cand_.size();
}

}  // namespace dc
