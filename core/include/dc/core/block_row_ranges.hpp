#pragma once
// A transpose product Jᵀx split into blocks of columns (whole bodies), each block summing the
// rows that reach it in ascending row order so that every block count gives the serial sums.
// A first pass records, per part q of the rows and per block t, the lowest and highest row of
// one-body rows (walls: they come first and reach every block) and of two-body rows acting on
// t: bounds[4·(parts·q + t) + {0, 1}] and [… + {2, 3}] (empty: lowest INT_MAX, highest −1).
// block_row_ranges folds those into the at most two row ranges block t walks.
#include <algorithm>
#include <limits>
#include <utility>

namespace dc {

/// Rows [lo1, hi1] then [lo2, hi2] (inclusive, ascending, disjoint; a range with lo > hi is
/// empty): every row some part recorded for the block, each once.
struct BlockRowRanges {
  int lo1, hi1, lo2, hi2;
};

inline BlockRowRanges block_row_ranges(const int* bounds, int parts, int block) {
  constexpr int kMax = std::numeric_limits<int>::max();
  BlockRowRanges r{kMax, -1, kMax, -1};
  for (int q = 0; q < parts; ++q) {
    const int* b = bounds + 4 * (parts * q + block);
    r.lo1 = std::min(r.lo1, b[0]);
    r.hi1 = std::max(r.hi1, b[1]);
    r.lo2 = std::min(r.lo2, b[2]);
    r.hi2 = std::max(r.hi2, b[3]);
  }
  if (r.lo1 <= r.hi1 && r.lo2 <= r.hi2 && !(r.hi1 < r.lo2 || r.hi2 < r.lo1)) {  // overlapping: one range
    r = {std::min(r.lo1, r.lo2), std::max(r.hi1, r.hi2), kMax, -1};
  } else if (r.lo2 < r.lo1) {
    std::swap(r.lo1, r.lo2);
    std::swap(r.hi1, r.hi2);
  }
  return r;
}

}  // namespace dc
