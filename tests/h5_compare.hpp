#pragma once
// Test helper shared by the suites: two HDF5 files hold the same datasets.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "dc/io/h5.hpp"

namespace dc::test {

/// Every dataset under `group` (recursively) of two files has equal shape, type and contents,
/// and both files have the same children in every group (a data set manifest's /shards aside).
inline void expect_same_datasets(const H5File& a, const H5File& b, const std::string& group = "/") {
  const auto names = a.children(group);
  ASSERT_EQ(names, b.children(group)) << group;
  for (const auto& n : names) {
    const std::string p = (group == "/" ? "/" : group + "/") + n;
    // A sharded data set's list of shard files names its run (a random id): not content.
    if (p == "/shards") continue;
    if (a.is_group(p)) {
      expect_same_datasets(a, b, p);
      continue;
    }
    ASSERT_EQ(a.shape(p), b.shape(p)) << p;
    ASSERT_EQ(a.type(p), b.type(p)) << p;
    switch (a.type(p)) {
      case H5Type::Float32: EXPECT_EQ(a.read<float>(p), b.read<float>(p)) << p; break;
      case H5Type::Float64: EXPECT_EQ(a.read<double>(p), b.read<double>(p)) << p; break;
      case H5Type::Int32: EXPECT_EQ(a.read<std::int32_t>(p), b.read<std::int32_t>(p)) << p; break;
      case H5Type::Int64: EXPECT_EQ(a.read<std::int64_t>(p), b.read<std::int64_t>(p)) << p; break;
      case H5Type::UInt8: EXPECT_EQ(a.read<std::uint8_t>(p), b.read<std::uint8_t>(p)) << p; break;
    }
  }
}

}  // namespace dc::test
