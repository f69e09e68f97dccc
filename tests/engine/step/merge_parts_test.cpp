// copy_lists_by_ranges: the lists concatenated after the array's untouched prefix, for lists
// of random sizes (empty ones among them), on 1, 2, 3 and 8 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "world/parts/merge_parts.hpp"

namespace dc {
namespace {

TEST(MergeParts, CopiesTheListsInOrderAfterThePrefixOnEveryThreadCount) {
  std::mt19937 rng(3);
  for (const int count : {1, 5, 40}) {
    std::vector<std::vector<int>> lists(static_cast<size_t>(count));
    int next = 0;
    for (auto& l : lists) {
      const int size = static_cast<int>(rng() % 4) == 0 ? 0 : static_cast<int>(rng() % 900);
      for (int k = 0; k < size; ++k) l.push_back(next++);
    }
    for (const size_t prefix : {size_t{0}, size_t{17}}) {
      std::vector<const std::vector<int>*> ptrs;
      std::vector<size_t> at{prefix};
      for (const auto& l : lists) {
        ptrs.push_back(&l);
        at.push_back(at.back() + l.size());
      }
      std::vector<int> expected(prefix, -1);
      for (const auto& l : lists) expected.insert(expected.end(), l.begin(), l.end());
      for (const int threads : {1, 2, 3, 8}) {
        std::vector<int> out(at.back(), -2);
        std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(prefix), -1);
        copy_lists_by_ranges<int>(threads, ptrs, at, out);
        EXPECT_EQ(expected, out) << count << " lists, prefix " << prefix << ", " << threads << " threads";
      }
    }
  }
}

}  // namespace
}  // namespace dc
