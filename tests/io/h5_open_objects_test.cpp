// Every error path of the HDF5 layer closes what it opened: after each failing call below,
// no HDF5 object is open (dc::h5_open_object_count() == 0). A leaked id would keep its file
// open and make libhdf5 print "infinite loop closing library" at exit (docs/robustness.md, finding 4).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/h5.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

class H5OpenObjects : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dc_h5_open_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                        "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    ASSERT_EQ(h5_open_object_count(), 0);
  }
  void TearDown() override { fs::remove_all(dir_); }
  [[nodiscard]] std::string file(const std::string& name) const { return (dir_ / name).string(); }

  /// Runs `fn`, which must throw IoError or InvalidArgument, and checks that nothing stays open.
  template <class Fn>
  void expect_error_closes_everything(Fn&& fn, const std::string& what) {
    bool threw = false;
    try {
      fn();
    } catch (const IoError&) {
      threw = true;
    } catch (const InvalidArgument&) {
      threw = true;
    }
    EXPECT_TRUE(threw) << what << ": no error";
    EXPECT_EQ(h5_open_object_count(), 0) << what << " left HDF5 objects open";
  }

  fs::path dir_;
};

TEST_F(H5OpenObjects, ReaderErrorPathsLeaveNothingOpen) {
  const std::string good = file("good.h5");
  {
    H5File out = H5File::create(good);
    out.write<double>("/a/x", std::vector<double>(12, 1.0), {3, 4});
    out.write_strings("/names", {"p", "q"});
    out.set_attribute("/", "format", "test");
    out.set_attribute<std::int32_t>("/a", "n", 3);
    EXPECT_GT(h5_open_object_count(), 0) << "an open file counts";
  }
  EXPECT_EQ(h5_open_object_count(), 0);

  const H5File in = H5File::open_read(good);
  const auto check = [&](auto&& fn, const std::string& what) {
    try {
      fn();
      ADD_FAILURE() << what << ": no error";
    } catch (const std::exception&) {
    }
    EXPECT_EQ(h5_open_object_count(), 1) << what << ": only the file itself may stay open";
  };
  check([&] { (void)in.read<double>("/a/x", {3, 5}); }, "wrong shape");
  check([&] { (void)in.read<std::int32_t>("/a/x"); }, "wrong type");
  check([&] { (void)in.read<double>("/a/missing"); }, "missing dataset");
  check([&] { (void)in.read_rows<double>("/a/x", 2, 5); }, "rows out of range");
  check([&] { (void)in.read_strings("/a/x"); }, "strings of a numeric dataset");
  check([&] { (void)in.attribute_string("/", "missing"); }, "missing attribute");
  check([&] { (void)in.attribute<double>("/", "format"); }, "string attribute read as a number");
  check([&] { (void)in.attribute_string("/a", "n"); }, "numeric attribute read as a string");
  check([&] { (void)in.children("/a/x"); }, "children of a dataset");
  check([&] { (void)in.attribute_names("/nope"); }, "attributes of a missing object");
}

TEST_F(H5OpenObjects, DamagedFilesLeaveNothingOpen) {
  const std::string big = file("big.h5");
  {
    H5File out = H5File::create(big);
    out.write<double>("/big", std::vector<double>(20000, 3.0), {20000});
    out.write_strings("/names", std::vector<std::string>(200, "a longer name than the rest"));
  }
  const auto bytes = fs::file_size(big);
  for (const auto keep : {bytes / 8, bytes / 2, bytes - 100}) {
    const std::string cut = file("cut_" + std::to_string(keep) + ".h5");
    fs::copy_file(big, cut);
    fs::resize_file(cut, keep);
    expect_error_closes_everything(
        [&] {
          const H5File in = H5File::open_read(cut);
          (void)in.read<double>("/big");
          (void)in.read_strings("/names");
        },
        "truncated to " + std::to_string(keep) + " bytes");
  }
  const std::string text = file("text.h5");
  std::ofstream(text) << "not HDF5\n";
  expect_error_closes_everything([&] { (void)H5File::open_read(text); }, "text file");
  expect_error_closes_everything([&] { (void)H5File::open_rw(file("missing.h5")); }, "missing file");
}

TEST_F(H5OpenObjects, AbandonedAtomicFileLeavesNothingOpenOrOnDisk) {
  const std::string path = file("atomic.h5");
  try {
    AtomicH5File out(path);
    out->write<double>("/v", std::vector<double>(10, 1.0), {10});
    throw std::runtime_error("writer failed half-way");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(h5_open_object_count(), 0);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  // A commit that cannot write (the directory is gone) is an IoError and leaves nothing.
  const std::string lost = file("gone/atomic.h5");
  expect_error_closes_everything(
      [&] {
        AtomicH5File out(lost);
        out->write<double>("/v", std::vector<double>(10, 1.0), {10});
        out.commit();
      },
      "commit into a missing directory");
  EXPECT_FALSE(fs::exists(lost + ".tmp"));
}

TEST(AtomicFile, ReplacesTheFileOrLeavesItUntouched) {
  const fs::path dir = fs::temp_directory_path() / "dc_atomic_file_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "a.json").string();
  write_file_atomically(path, "first");
  write_file_atomically(path, "second, longer");
  std::ifstream in(path);
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, "second, longer");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  // Renaming onto a directory fails: the IoError names the file and the temporary is removed.
  fs::create_directories(dir / "d.json");
  try {
    write_file_atomically((dir / "d.json").string(), "x");
    ADD_FAILURE() << "renaming onto a directory succeeded";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("d.json"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(dir / "d.json.tmp"));
  EXPECT_THROW(write_file_atomically((dir / "no/such/x").string(), "x"), IoError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dc
