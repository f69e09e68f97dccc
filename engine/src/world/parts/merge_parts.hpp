#pragma once
// The merge of a stage's per-job lists into one array (World's contact lists) by jobs of output
// ranges: job p copies the pieces of the lists that fall in items [part_begin(p),
// part_begin(p + 1)) of the array, the split the next stage (assembly's jobs of contacts) uses,
// so with WorkTeam::for_parts' blocks of jobs per member a core copies the contacts it then
// assembles. The array is the same for every split.
#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

#include "world/parts/step_parts.hpp"

namespace dc {

/// Copies *lists[i] to out[at[i], at[i + 1]) for every i (at: lists.size() + 1 ascending offsets,
/// at.back() = out.size(); out[0, at[0]) is left as it is) on `threads` threads.
template <class T>
void copy_lists_by_ranges(int threads, std::span<const std::vector<T>* const> lists, std::span<const std::size_t> at,
                          std::vector<T>& out) {
  const long n = static_cast<long>(out.size());
  const int jobs = parts_for(threads, n, 4, 1024);
  run_parts(threads, jobs, [&](int p) {
    const auto lo = static_cast<std::size_t>(std::max(static_cast<long>(at.front()), part_begin(n, jobs, p)));
    const auto hi = static_cast<std::size_t>(part_begin(n, jobs, p + 1));
    if (lo >= hi) return;
    for (auto i = static_cast<std::size_t>(std::upper_bound(at.begin(), at.end(), lo) - at.begin()) - 1;
         i < lists.size() && at[i] < hi; ++i) {
      const std::size_t from = std::max(lo, at[i]), to = std::min(hi, at[i + 1]);
      if (from >= to) continue;
      const auto first = lists[i]->begin() + static_cast<std::ptrdiff_t>(from - at[i]);
      std::copy(first, first + static_cast<std::ptrdiff_t>(to - from), out.begin() + static_cast<std::ptrdiff_t>(from));
    }
  });
}

}  // namespace dc
