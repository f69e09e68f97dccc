// HDF5 helpers (io/include/dc/io/h5.hpp): round trips of every element type and
// rank, extendible compressed datasets across reopen, attributes, atomic commit/abandon,
// and the IoErrors for damaged files and shape mismatches.
#include <gtest/gtest.h>

#include <filesystem>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numeric>
#include <string>

#include "dc/core/error.hpp"
#include "io/io_error.hpp"
#include "dc/io/h5.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

#define EXPECT_CONTAINS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << "message: " << (haystack)

using test::io_error;

/// A fresh directory per test, removed afterwards.
class H5Test : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("dc_h5_") + info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

template <H5Element T>
std::vector<T> iota_values(std::size_t n) {
  std::vector<T> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<T>(i % 200) + (std::is_floating_point_v<T> ? T(0.25) : T(0));
  return v;
}

template <H5Element T>
void round_trip_all_ranks(H5File& out, const std::string& prefix) {
  const std::vector<H5Shape> shapes = {{}, {7}, {3, 5}, {2, 3, 4}, {2, 1, 3, 2}, {0, 4}};
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    const H5Shape& shape = shapes[s];
    hsize_t n = 1;
    for (hsize_t d : shape) n *= d;
    out.write<T>(prefix + "/r" + std::to_string(s), iota_values<T>(n), shape);
  }
}

template <H5Element T>
void check_all_ranks(const H5File& in, const std::string& prefix, H5Type type) {
  const std::vector<H5Shape> shapes = {{}, {7}, {3, 5}, {2, 3, 4}, {2, 1, 3, 2}, {0, 4}};
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    const std::string path = prefix + "/r" + std::to_string(s);
    SCOPED_TRACE(path);
    hsize_t n = 1;
    for (hsize_t d : shapes[s]) n *= d;
    EXPECT_EQ(in.shape(path), shapes[s]);
    EXPECT_EQ(in.type(path), type);
    EXPECT_EQ(in.read<T>(path, shapes[s]), iota_values<T>(n));
  }
}

TEST_F(H5Test, RoundTripEveryTypeAndRank) {
  const std::string path = file("types.h5");
  {
    H5File out = H5File::create(path);
    round_trip_all_ranks<double>(out, "/f64");
    round_trip_all_ranks<float>(out, "/f32");
    round_trip_all_ranks<std::int32_t>(out, "/i32");
    round_trip_all_ranks<std::int64_t>(out, "/deep/er/i64");
    round_trip_all_ranks<std::uint8_t>(out, "u8");  // leading '/' optional
    out.close();
  }
  const H5File in = H5File::open_read(path);
  check_all_ranks<double>(in, "/f64", H5Type::Float64);
  check_all_ranks<float>(in, "/f32", H5Type::Float32);
  check_all_ranks<std::int32_t>(in, "/i32", H5Type::Int32);
  check_all_ranks<std::int64_t>(in, "/deep/er/i64", H5Type::Int64);
  check_all_ranks<std::uint8_t>(in, "/u8", H5Type::UInt8);
  EXPECT_TRUE(in.is_group("/deep/er"));
  EXPECT_EQ(in.children("/"), (std::vector<std::string>{"deep", "f32", "f64", "i32", "u8"}));
}

TEST_F(H5Test, ExtremeValuesSurvive) {
  const std::string path = file("extreme.h5");
  const std::vector<double> d = {0.0, -0.0, 1e-308, 5e-324, 1.7976931348623157e308,
                                 std::numeric_limits<double>::infinity(), 0.1 + 0.2};
  const std::vector<std::int64_t> i = {std::numeric_limits<std::int64_t>::min(), -1, 0,
                                       std::numeric_limits<std::int64_t>::max()};
  {
    H5File out = H5File::create(path);
    out.write<double>("d", d, {d.size()});
    out.write<std::int64_t>("i", i, {i.size()});
  }
  const H5File in = H5File::open_read(path);
  const auto d2 = in.read<double>("d");
  ASSERT_EQ(d2.size(), d.size());
  for (std::size_t k = 0; k < d.size(); ++k) EXPECT_EQ(std::memcmp(&d[k], &d2[k], sizeof(double)), 0) << k;
  EXPECT_EQ(in.read<std::int64_t>("i"), i);
}

TEST_F(H5Test, LosslessWideningOnReadOnly) {
  const std::string path = file("widen.h5");
  {
    H5File out = H5File::create(path);
    out.write<float>("f", std::vector<float>{0.5f, 1.25f}, {2});
    out.write<std::int32_t>("i", std::vector<std::int32_t>{-3, 4}, {2});
    out.write<double>("d", std::vector<double>{0.1}, {1});
  }
  const H5File in = H5File::open_read(path);
  EXPECT_EQ(in.read<double>("f"), (std::vector<double>{0.5, 1.25}));
  EXPECT_EQ(in.read<std::int64_t>("i"), (std::vector<std::int64_t>{-3, 4}));
  EXPECT_EQ(in.read<double>("i"), (std::vector<double>{-3.0, 4.0}));
  EXPECT_CONTAINS(io_error([&] { (void)in.read<float>("d"); }), "dataset holds float64 but float32 was requested");
  EXPECT_CONTAINS(io_error([&] { (void)in.read<std::int32_t>("f"); }), "/f");
}

TEST_F(H5Test, AppendRowsToExtendibleCompressedDatasetAcrossReopen) {
  const std::string path = file("append.h5");
  const hsize_t cols = 3;
  std::vector<double> all;
  {
    H5File out = H5File::create(path);
    out.create_dataset<double>("/steps/lambda", {0, 2, cols}, {.extendible = true, .chunk_rows = 4, .deflate = 6});
    out.create_dataset<std::int32_t>("/steps/index", {0}, {.extendible = true});
    for (int step = 0; step < 10; ++step) {
      std::vector<double> row(2 * cols);
      std::iota(row.begin(), row.end(), 100.0 * step);
      all.insert(all.end(), row.begin(), row.end());
      EXPECT_EQ(out.append_rows<double>("/steps/lambda", row), static_cast<hsize_t>(step + 1));
      out.append_rows<std::int32_t>("/steps/index", std::vector<std::int32_t>{step});
    }
  }
  {
    H5File more = H5File::open_rw(path);  // resume
    EXPECT_EQ(more.shape("/steps/lambda"), (H5Shape{10, 2, cols}));
    std::vector<double> two(2 * 2 * cols);
    std::iota(two.begin(), two.end(), 5000.0);
    all.insert(all.end(), two.begin(), two.end());
    EXPECT_EQ(more.append_rows<double>("/steps/lambda", two), 12u);  // two rows at once
    more.append_rows<std::int32_t>("/steps/index", std::vector<std::int32_t>{10, 11});
  }
  const H5File in = H5File::open_read(path);
  EXPECT_EQ(in.read<double>("/steps/lambda", {kH5Any, 2, cols}), all);
  const auto rows = in.read_rows<double>("/steps/lambda", 3, 2);
  EXPECT_EQ(rows, std::vector<double>(all.begin() + 3 * 2 * cols, all.begin() + 5 * 2 * cols));
  EXPECT_EQ(in.read_rows<double>("/steps/lambda", 12, 0).size(), 0u);
  EXPECT_CONTAINS(io_error([&] { (void)in.read_rows<double>("/steps/lambda", 11, 2); }), "outside");
  std::vector<std::int32_t> idx(12);
  std::iota(idx.begin(), idx.end(), 0);
  EXPECT_EQ(in.read<std::int32_t>("/steps/index"), idx);
}

TEST_F(H5Test, CompressionShrinksRedundantData) {
  const std::string plain = file("plain.h5"), packed = file("packed.h5");
  const std::vector<double> zeros(200000, 1.5);
  H5File::create(plain).write<double>("x", zeros, {1000, 200});
  H5File::create(packed).write<double>("x", zeros, {1000, 200}, {.deflate = 9});
  EXPECT_LT(fs::file_size(packed) * 10, fs::file_size(plain));
  EXPECT_EQ(H5File::open_read(packed).read<double>("x"), zeros);
}

TEST_F(H5Test, ResizeAndOverwriteRows) {
  const std::string path = file("resize.h5");
  H5File f = H5File::create(path);
  f.create_dataset<std::int64_t>("r", {0, 2}, {.extendible = true});
  f.append_rows<std::int64_t>("r", std::vector<std::int64_t>{1, 2, 3, 4, 5, 6});
  f.resize_rows("r", 2);  // drop the last, e.g. an incomplete record after a crash
  EXPECT_EQ(f.read<std::int64_t>("r"), (std::vector<std::int64_t>{1, 2, 3, 4}));
  f.write_rows<std::int64_t>("r", 1, std::vector<std::int64_t>{9, 9});
  EXPECT_EQ(f.read<std::int64_t>("r"), (std::vector<std::int64_t>{1, 2, 9, 9}));
  EXPECT_CONTAINS(io_error([&] { f.write_rows<std::int64_t>("r", 2, std::vector<std::int64_t>{0, 0}); }), "outside");
  f.write<double>("fixed", std::vector<double>{1, 2}, {2});
  EXPECT_CONTAINS(io_error([&] { f.append_rows<double>("fixed", std::vector<double>{3}); }), "not extendible");
  EXPECT_CONTAINS(io_error([&] { f.append_rows<double>("r", std::vector<double>{3, 4}); }), "holds int64");
  EXPECT_THROW(f.append_rows<std::int64_t>("r", std::vector<std::int64_t>{1, 2, 3}), InvalidArgument);
}

TEST_F(H5Test, GroupsExistenceAndRemoval) {
  H5File f = H5File::create(file("groups.h5"));
  EXPECT_TRUE(f.exists("/"));
  EXPECT_FALSE(f.exists("/a"));
  EXPECT_FALSE(f.exists("/a/b/c"));  // missing parents are a plain "no"
  f.create_group("/a/b/c");
  f.create_group("/a/b/c");  // idempotent
  EXPECT_TRUE(f.is_group("/a/b"));
  EXPECT_FALSE(f.is_dataset("/a/b"));
  f.write<double>("/a/x", std::vector<double>{1}, {1});
  EXPECT_TRUE(f.is_dataset("/a/x"));
  EXPECT_FALSE(f.exists("/a/x/y"));  // a dataset has no children
  EXPECT_EQ(f.children("/a"), (std::vector<std::string>{"b", "x"}));
  EXPECT_CONTAINS(io_error([&] { f.write<double>("/a/x", std::vector<double>{2}, {1}); }), "/a/x");
  EXPECT_CONTAINS(io_error([&] { f.create_group("/a/x"); }), "/a/x");
  f.remove("/a/x");
  EXPECT_FALSE(f.exists("/a/x"));
  f.write<double>("/a/x", std::vector<double>{2}, {1});
  EXPECT_EQ(f.read<double>("/a/x"), std::vector<double>{2});
  EXPECT_CONTAINS(io_error([&] { (void)f.read<double>("/nope"); }), "/nope");
}

TEST_F(H5Test, StringDatasets) {
  const std::string path = file("strings.h5");
  const std::vector<std::string> names = {"zero", "builtin", "", "cnn — ünïcode"};
  {
    H5File out = H5File::create(path);
    out.write_strings("/var", names);
    out.write_strings("/fixed", names, H5StringKind::Fixed);
    out.write_strings("/empty", {});
  }
  const H5File in = H5File::open_read(path);
  EXPECT_EQ(in.read_strings("/var"), names);
  EXPECT_EQ(in.read_strings("/fixed"), names);
  EXPECT_TRUE(in.read_strings("/empty").empty());
}

TEST_F(H5Test, AttributesOnRootGroupsAndDatasets) {
  const std::string path = file("attrs.h5");
  {
    H5File out = H5File::create(path);
    out.write<float>("/g/d", std::vector<float>{1, 2}, {2});
    out.set_attribute("/", "format", "deepcontact-test");
    out.set_attribute("/", "version", std::int32_t{3});
    out.set_attribute("/g", "dt", 0.01);
    out.set_attribute("/g", "label", "fixed length", H5StringKind::Fixed);
    out.set_attribute("/g/d", "unit", "N s");
    out.set_attribute("/g/d", "steps", std::int64_t{600});
    out.set_attribute("/g/d", "flag", std::uint8_t{1});
    out.set_attribute("/g/d", "scale", 2.5f);
    const std::vector<double> mean = {15.0, 15.5};
    out.set_attribute_array<double>("/g", "mean", mean);
    out.set_attribute("/", "version", std::int32_t{4});  // replaced, not duplicated
    out.set_attribute("/g", "dt", "now a string");       // replaced with another type
    out.set_attribute("/", "empty", "");
  }
  const H5File in = H5File::open_read(path);
  EXPECT_EQ(in.attribute_string("/", "format"), "deepcontact-test");
  EXPECT_EQ(in.attribute<std::int32_t>("/", "version"), 4);
  EXPECT_EQ(in.attribute<std::int64_t>("/", "version"), 4);
  EXPECT_EQ(in.attribute_string("/g", "dt"), "now a string");
  EXPECT_EQ(in.attribute_string("/g", "label"), "fixed length");
  EXPECT_EQ(in.attribute_string("/g/d", "unit"), "N s");
  EXPECT_EQ(in.attribute<std::int64_t>("/g/d", "steps"), 600);
  EXPECT_EQ(in.attribute<std::uint8_t>("/g/d", "flag"), 1);
  EXPECT_EQ(in.attribute<float>("/g/d", "scale"), 2.5f);
  EXPECT_EQ(in.attribute_array<double>("/g", "mean"), (std::vector<double>{15.0, 15.5}));
  EXPECT_EQ(in.attribute_string("/", "empty"), "");
  EXPECT_TRUE(in.has_attribute("/g/d", "unit"));
  EXPECT_FALSE(in.has_attribute("/g/d", "nope"));
  EXPECT_EQ(in.attribute_names("/"), (std::vector<std::string>{"empty", "format", "version"}));
  EXPECT_CONTAINS(io_error([&] { (void)in.attribute<double>("/g", "nope"); }), "attribute 'nope'");
  EXPECT_CONTAINS(io_error([&] { (void)in.attribute<double>("/g", "mean"); }), "2 values");
  EXPECT_CONTAINS(io_error([&] { (void)in.attribute<double>("/", "format"); }), "format");
  EXPECT_CONTAINS(io_error([&] { (void)in.attribute_string("/", "version"); }), "not a string");
}

TEST_F(H5Test, ReadOnlyFilesRefuseWrites) {
  const std::string path = file("ro.h5");
  H5File::create(path).write<double>("x", std::vector<double>{1}, {1});
  H5File in = H5File::open_read(path);
  EXPECT_FALSE(in.writable());
  EXPECT_CONTAINS(io_error([&] { in.write<double>("y", std::vector<double>{1}, {1}); }), "read-only");
  EXPECT_CONTAINS(io_error([&] { in.set_attribute("/", "a", 1.0); }), "read-only");
  in.close();
  EXPECT_THROW((void)in.read<double>("x"), InvalidArgument);
}

TEST_F(H5Test, AtomicCommitReplacesTheFile) {
  const std::string path = file("atomic.h5");
  {
    AtomicH5File out(path);
    EXPECT_FALSE(fs::exists(path + ".tmp")) << "built in memory: nothing on disk before commit()";
    EXPECT_FALSE(fs::exists(path));
    out->write<double>("v", std::vector<double>{1}, {1});
    out.commit();
    EXPECT_THROW(out.file(), InvalidArgument);
  }
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  EXPECT_EQ(H5File::open_read(path).read<double>("v"), std::vector<double>{1});
  {
    AtomicH5File out(path);
    out->write<double>("v", std::vector<double>{2}, {1});
    out.commit();
  }
  EXPECT_EQ(H5File::open_read(path).read<double>("v"), std::vector<double>{2});
}

TEST_F(H5Test, AtomicAbandonLeavesTheOldFile) {
  const std::string path = file("abandon.h5");
  {
    AtomicH5File out(path);
    out->write<double>("v", std::vector<double>{1}, {1});
    out.commit();
  }
  try {
    AtomicH5File out(path);
    out->write<double>("v", std::vector<double>{99}, {1});
    throw std::runtime_error("writer failed half-way");
  } catch (const std::runtime_error&) {
  }
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  EXPECT_EQ(H5File::open_read(path).read<double>("v"), std::vector<double>{1});
  // Abandoning a file that never existed leaves nothing behind.
  { AtomicH5File out(file("never.h5")); }
  EXPECT_FALSE(fs::exists(file("never.h5")));
  EXPECT_FALSE(fs::exists(file("never.h5.tmp")));
}

TEST_F(H5Test, MissingTextAndTruncatedFilesAreIoErrors) {
  const std::string missing = file("missing.h5");
  EXPECT_CONTAINS(io_error([&] { H5File::open_read(missing); }), missing);
  EXPECT_CONTAINS(io_error([&] { H5File::open_read(dir_.string()); }), "not a regular file");

  const std::string text = file("text.h5");
  std::ofstream(text) << "this is not an HDF5 file\n";
  EXPECT_CONTAINS(io_error([&] { H5File::open_read(text); }), "not an HDF5 file");
  EXPECT_CONTAINS(io_error([&] { H5File::open_rw(text); }), text);
  const std::string empty = file("empty.h5");
  std::ofstream{empty};
  EXPECT_CONTAINS(io_error([&] { H5File::open_read(empty); }), empty);

  const std::string truncated = file("truncated.h5");
  {
    H5File out = H5File::create(truncated);
    out.write<double>("/big", std::vector<double>(20000, 3.0), {20000});
  }
  fs::resize_file(truncated, fs::file_size(truncated) / 2);
  const std::string m = io_error([&] { (void)H5File::open_read(truncated).read<double>("/big"); });
  EXPECT_CONTAINS(m, truncated);
  EXPECT_EQ(m.find('\n'), std::string::npos);
  EXPECT_CONTAINS(io_error([&] { H5File::create(file("no/such/dir/x.h5")); }), "no/such/dir/x.h5");
}

TEST_F(H5Test, ShapeMismatchNamesFileObjectAndShapes) {
  const std::string path = file("results.h5");
  H5File::create(path).write<double>("/bodies/position", std::vector<double>(15), {3, 5});
  const H5File in = H5File::open_read(path);
  const std::string m = io_error([&] { (void)in.read<double>("/bodies/position", {3, 5, 2}); });
  EXPECT_EQ(m, path + ": /bodies/position: dataset has shape (3,5) but (3,5,2) was expected");
  EXPECT_NO_THROW(in.require_shape("/bodies/position", {kH5Any, 5}));
  EXPECT_CONTAINS(io_error([&] { in.require_shape("/bodies/position", {kH5Any, 4}); }), "(*,4)");
  EXPECT_THROW(H5File::create(file("x.h5")).write<double>("a", std::vector<double>(5), {2, 2}), InvalidArgument);
}

// A virtual dataset concatenates rows of other files (the data set manifest's bulk
// datasets): read whole and by rows it equals the concatenation; source paths are relative
// to the virtual file's folder (found from any working directory); a missing source reads
// as NaN, not as numbers.
TEST_F(H5Test, VirtualDatasetConcatenatesRowsOfOtherFiles) {
  fs::create_directories(file("parts"));
  const std::vector<double> a = {1, 2, 3, 4}, b = {5, 6, 7, 8, 9, 10};
  {
    H5File f = H5File::create(file("parts/a.h5"));
    f.write<double>("/x", a, {2, 2});
    H5File g = H5File::create(file("parts/b.h5"));
    g.write<double>("/y", b, {3, 2});
  }
  {
    AtomicH5File v(file("v.h5"));
    v->create_virtual<double>("/all", {2}, {{"parts/a.h5", "/x", 2}, {"parts/b.h5", "/y", 3}});
    v->create_virtual<double>("/none", {2}, {});
    v.commit();
  }
  std::vector<double> both = a;
  both.insert(both.end(), b.begin(), b.end());
  const H5File v = H5File::open_read(file("v.h5"));
  EXPECT_EQ(v.shape("/all"), (H5Shape{5, 2}));
  EXPECT_EQ(v.read<double>("/all"), both);
  EXPECT_EQ(v.read_rows<double>("/all", 1, 2), (std::vector<double>{3, 4, 5, 6}));
  EXPECT_EQ(v.shape("/none"), (H5Shape{0, 2}));
  fs::rename(file("parts/b.h5"), file("parts/gone.h5"));
  const std::vector<double> missing = H5File::open_read(file("v.h5")).read_rows<double>("/all", 2, 1);
  EXPECT_TRUE(std::isnan(missing[0]) && std::isnan(missing[1]));
}

}  // namespace
}  // namespace dc
