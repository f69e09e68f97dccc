// H5File::require_in_file and copy_h5_file: data that is not stored in the file itself (an
// external link, a virtual dataset, external raw storage) is refused with one line naming the
// object; HDF5 would read a missing source as zeros. Links and storage are made with HDF5's C
// API here (this layer writes none of them except virtual datasets).
#include <gtest/gtest.h>
#include <hdf5.h>

#include <filesystem>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "dc/io/h5_copy.hpp"
#include "io/io_error.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

class H5InFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           (std::string("dc_h5_in_file_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  /// A file with /group/local (a dataset of its own), /group/ext (external link to
  /// source.h5:/x), /dangling (external link to a missing file) and /raw (external storage).
  std::string linked_file() {
    {
      H5File src = H5File::create(file("source.h5"));
      src.write<double>("/x", std::vector<double>{1, 2, 3}, {3});
    }
    const std::string path = file("linked.h5");
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hid_t g = H5Gcreate2(f, "/group", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t n = 3;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t local = H5Dcreate2(f, "/group/local", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const double v[3] = {4, 5, 6};
    H5Dwrite(local, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
    H5Lcreate_external("source.h5", "/x", f, "/group/ext", H5P_DEFAULT, H5P_DEFAULT);
    H5Lcreate_external("missing.h5", "/x", f, "/dangling", H5P_DEFAULT, H5P_DEFAULT);
    H5Lcreate_soft("/group/ext", f, "/soft", H5P_DEFAULT, H5P_DEFAULT);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_external(dcpl, file("raw.bin").c_str(), 0, n * sizeof(double));
    const hid_t raw = H5Dcreate2(f, "/raw", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    for (hid_t id : {raw, local}) H5Dclose(id);
    H5Pclose(dcpl);
    H5Sclose(space);
    H5Gclose(g);
    H5Fclose(f);
    return path;
  }

  fs::path dir_;
};

TEST_F(H5InFile, ObjectsStoredElsewhereAreRefusedNamingThem) {
  const std::string path = linked_file();
  const H5File f = H5File::open_read(path);
  EXPECT_NO_THROW(f.require_in_file("/group/local"));
  EXPECT_NO_THROW(f.require_in_file("/group"));
  EXPECT_NO_THROW(f.require_in_file("/not/there"));  // absent: the caller's read names it
  const std::string ext = test::io_error([&] { f.require_in_file("/group/ext"); });
  EXPECT_NE(ext.find("/group/ext: reached through an external link (/group/ext)"), std::string::npos) << ext;
  const std::string dangling = test::io_error([&] { f.require_in_file("/dangling"); });
  EXPECT_NE(dangling.find("external link"), std::string::npos) << dangling;
  const std::string soft = test::io_error([&] { f.require_in_file("/soft"); });
  EXPECT_NE(soft.find("/soft: is stored in another file"), std::string::npos) << soft;
  const std::string raw = test::io_error([&] { f.require_in_file("/raw"); });
  EXPECT_NE(raw.find("/raw: keeps its values in external raw files"), std::string::npos) << raw;
  for (const std::string& m : {ext, dangling, soft, raw}) EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

// Before: copy_hdf5 turned a virtual dataset with a missing source into a checksummed file of
// NaNs (zeros for integers), and followed external links into the copy.
TEST_F(H5InFile, CopyRefusesDataFromOtherFilesAndWritesNothing) {
  {
    H5File part = H5File::create(file("part.h5"));
    part.write<std::int32_t>("/x", std::vector<std::int32_t>{1, 2}, {2});
    AtomicH5File v(file("virtual.h5"));
    v->create_virtual<std::int32_t>("/all", {}, {{"part.h5", "/x", 2}});
    v.commit();
  }
  const std::string virt = test::io_error([&] { copy_h5_file(file("virtual.h5"), file("copy.h5")); });
  EXPECT_NE(virt.find("/all: is a virtual dataset"), std::string::npos) << virt;
  const std::string linked = test::io_error([&] { copy_h5_file(linked_file(), file("copy.h5")); });
  EXPECT_NE(linked.find("external"), std::string::npos) << linked;
  EXPECT_FALSE(fs::exists(file("copy.h5")));
}

}  // namespace
}  // namespace dc
