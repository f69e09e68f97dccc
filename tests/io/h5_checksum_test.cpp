// Checksums of the HDF5 layer (docs/formats.md "Checksums"): every value a file of this layer
// holds is covered, so a flipped bit is an IoError naming the damage — never a changed value
// read without a word. Files written before checksums still load, and copy_h5_file gives
// them checksums with every value bit-equal.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <numeric>

#include "dc/core/error.hpp"
#include "io/io_error.hpp"
#include "dc/io/h5.hpp"
#include "dc/io/h5_copy.hpp"
#include "io/bit_flips.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

/// A file with every kind of object this layer writes.
void write_every_kind(const std::string& path) {
  AtomicH5File out(path);
  H5File& f = out.file();
  std::vector<double> big(4000);
  std::iota(big.begin(), big.end(), 0.5);
  f.write<double>("/data/big", big, {1000, 4});
  f.create_dataset<float>("/data/rows", {0, 8}, {.extendible = true, .deflate = 4});
  std::vector<float> rows(8 * 50);
  std::iota(rows.begin(), rows.end(), 1.0f);
  f.append_rows<float>("/data/rows", rows);
  f.write<std::int32_t>("/data/scalar", std::vector<std::int32_t>{7}, {});
  f.write<std::int64_t>("/data/empty", std::vector<std::int64_t>{}, {0});
  f.write<std::uint8_t>("/data/bytes", std::vector<std::uint8_t>{1, 2, 3}, {3});
  f.write_strings("/text/variable", {"alpha", "beta", "gamma"});
  f.write_strings("/text/fixed", {"one", "two"}, H5StringKind::Fixed);
  f.set_attribute("/", "format", "every-kind");
  f.set_attribute("/", "fixed", "fixed text", H5StringKind::Fixed);
  f.set_attribute<double>("/data", "scale", 2.5);
  f.set_attribute_array<std::int32_t>("/data/big", "dims", std::vector<std::int32_t>{1000, 4});
  out.commit();
}

TEST(H5Checksum, NoBitFlipChangesAValueSilently) {
  test::TempDir dir;
  const std::string file = dir / "every.h5";
  write_every_kind(file);
  const test::BitFlipCounts n = test::flip_random_bits(file, 400, 1, dir / "flipped.h5");
  EXPECT_EQ(n.silent, 0) << "silent flips, e.g. " << (n.silent_bits.empty() ? "" : n.silent_bits.front());
  EXPECT_GT(n.detected, 0);
}

/// Index of the first occurrence of `needle` in the file's bytes.
std::size_t find_bytes(const std::string& file, const std::string& needle) {
  const std::size_t at = test::read_bytes(file).find(needle);
  EXPECT_NE(at, std::string::npos) << "pattern not in " << file;
  return at;
}

void flip_bit_at(const std::string& file, std::size_t byte) {
  std::string bytes = test::read_bytes(file);
  bytes[byte] = static_cast<char>(bytes[byte] ^ 0x10);
  test::write_bytes(file, bytes);
}

using test::io_error;

TEST(H5Checksum, ADamagedChunkOrStringIsAOneLineErrorNamingTheObject) {
  test::TempDir dir;
  const std::string file = dir / "values.h5";
  {
    AtomicH5File out(file);
    out->write<double>("/weights", std::vector<double>(64, 1234.5678), {8, 8});
    // Variable-length strings: their bytes are in the global heap, checked by the stored hash.
    out->set_attribute("/", "note", "a distinctive note", H5StringKind::Variable);
    out->write_strings("/names", {"a distinctive name"}, H5StringKind::Variable);
    out.commit();
  }
  double v = 1234.5678;
  std::string pattern(sizeof v, '\0');
  std::memcpy(pattern.data(), &v, sizeof v);
  flip_bit_at(file, find_bytes(file, pattern) + 3);
  flip_bit_at(file, find_bytes(file, "distinctive note") + 2);
  flip_bit_at(file, find_bytes(file, "distinctive name") + 2);
  const H5File f = H5File::open_read(file);
  for (const std::string& m : {io_error([&] { (void)f.read<double>("/weights"); }),
                               io_error([&] { (void)f.attribute_string("/", "note"); }),
                               io_error([&] { (void)f.read_strings("/names"); })}) {
    EXPECT_NE(m.find("checksum mismatch: the file is damaged"), std::string::npos) << m;
    EXPECT_NE(m.find(file), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(H5Checksum, AFileWithoutChecksumsLoadsAndItsCopyHasThemWithEqualValues) {
  test::TempDir dir;
  const std::string old = std::string(DC_SOURCE_DIR) + "/tests/io/data/trajectory-before-checksums.h5";
  const std::string before = test::dump_h5(old);  // read without the checksum test
  const std::string copy = dir / "copy.h5";
  copy_h5_file(old, copy);
  EXPECT_EQ(test::dump_h5(copy), before);
  EXPECT_EQ(test::flip_random_bits(copy, 100, 2, dir / "flipped.h5").silent, 0);
  // One flip in a body's mass (π for unit circles): read silently from the old file, refused
  // in the copy. (Random flips of the old file could hit its global heap, whose damage
  // crashes libhdf5 itself: see H5StringKind.)
  const double pi = 3.141592653589793;
  std::string pattern(sizeof pi, '\0');
  std::memcpy(pattern.data(), &pi, sizeof pi);
  const std::string damaged_old = dir / "old.h5", damaged_copy = dir / "copy-damaged.h5";
  std::filesystem::copy_file(old, damaged_old);
  std::filesystem::copy_file(copy, damaged_copy);
  flip_bit_at(damaged_old, find_bytes(damaged_old, pattern) + 2);
  flip_bit_at(damaged_copy, find_bytes(damaged_copy, pattern) + 2);
  EXPECT_NE(test::dump_h5(damaged_old), before) << "the flip should change a value of the unchecked file";
  EXPECT_NE(io_error([&] { (void)test::dump_h5(damaged_copy); }).find("checksum mismatch"), std::string::npos);
}

TEST(H5Checksum, TheShippedModelDetectsEveryFlipThatChangesAValue) {
  test::TempDir dir;
  const test::BitFlipCounts n =
      test::flip_random_bits(std::string(DC_SOURCE_DIR) + "/models/default.h5", 100, 3, dir / "flipped.h5");
  EXPECT_EQ(n.silent, 0) << n.silent << " silent flips, e.g. " << (n.silent_bits.empty() ? "" : n.silent_bits.front());
}

// A virtual dataset keeps its source mappings in HDF5's global heap, which has no checksum:
// damaged mappings made libhdf5 1.10.8 abort or crash in H5Dopen. A file sealed with a hash of
// all its bytes (AtomicH5File::add_whole_file_hash, what data set manifests use) is checked
// before libhdf5 reads it: a flip in every byte of the heap — and of the trailer's length and
// hash — is a one-line error; h5py-style readers that ignore the trailer read it unchanged.
TEST(H5Checksum, ASealedFileRefusesEveryFlipOfItsVirtualDatasetMappings) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "parts");
  H5File::create(dir / "parts/a.h5").write<double>("/x", std::vector<double>{1, 2, 3, 4}, {2, 2});
  H5File::create(dir / "parts/b.h5").write<double>("/y", std::vector<double>{5, 6, 7, 8, 9, 10}, {3, 2});
  const std::string file = dir / "v.h5";
  {
    AtomicH5File v(file);
    v.add_whole_file_hash();
    v->create_virtual<double>("/all", {2}, {{"parts/a.h5", "/x", 2}, {"parts/b.h5", "/y", 3}});
    v.commit();
  }
  const std::string reference = test::dump_h5(file);
  EXPECT_NE(reference.find("all"), std::string::npos);
  const std::string bytes = test::read_bytes(file);
  const std::size_t heap = find_bytes(file, "GCOL"), trailer = bytes.size() - 24;
  std::vector<std::size_t> damaged_bytes;  // the heap collection (≥ 4 KiB), then the trailer's length and hash
  for (std::size_t b = heap; b < std::min(heap + 4096, trailer); ++b) damaged_bytes.push_back(b);
  for (std::size_t b = trailer + 8; b < bytes.size(); ++b) damaged_bytes.push_back(b);
  const std::string flipped = dir / "flipped.h5";
  int refused = 0;
  for (const std::size_t byte : damaged_bytes) {  // one bit per byte, each bit position in turn
    std::string d = bytes;
    d[byte] = static_cast<char>(d[byte] ^ (1 << (byte % 8)));
    test::write_bytes(flipped, d);
    const std::string m = io_error([&] { (void)H5File::open_read(flipped); });
    refused += m.find("checksum mismatch: the file is damaged") != std::string::npos && m.find('\n') == std::string::npos;
  }
  EXPECT_EQ(refused, static_cast<int>(damaged_bytes.size()));
  // Opened for writing, the seal is dropped first (HDF5 may change any byte), and the file
  // still reads the same.
  H5File::open_rw(file).close();
  EXPECT_EQ(std::filesystem::file_size(file), bytes.size() - 24);
  EXPECT_EQ(test::dump_h5(file), reference);
}

// scripts/bitflip-test.sh: DC_BITFLIP_FILE, DC_BITFLIP_COUNT (100), DC_BITFLIP_SEED (1).
TEST(H5Checksum, FlipsOfTheFileNamedByTheEnvironment) {
  const char* file = std::getenv("DC_BITFLIP_FILE");
  if (file == nullptr) GTEST_SKIP() << "DC_BITFLIP_FILE is not set (scripts/bitflip-test.sh sets it)";
  const char* count = std::getenv("DC_BITFLIP_COUNT");
  const char* seed = std::getenv("DC_BITFLIP_SEED");
  // The damaged copy sits next to the file: a data set's manifest finds its shards by
  // relative paths.
  const test::BitFlipCounts n = test::flip_random_bits(file, count ? std::atoi(count) : 100,
                                                       seed ? std::strtoull(seed, nullptr, 10) : 1,
                                                       std::string(file) + ".flipped.h5");
  std::printf("bitflip %s: %d flips: %d detected, %d harmless (unused bytes: every value unchanged), %d accepted "
              "silently\n  first error: %s\n",
              file, n.detected + n.harmless + n.silent, n.detected, n.harmless, n.silent, n.first_error.c_str());
  for (const auto& b : n.silent_bits) std::printf("  silent: %s\n", b.c_str());
  for (const auto& b : n.leaked_bits) std::printf("  libhdf5 could not close the file after: %s\n", b.c_str());
  EXPECT_EQ(n.silent, 0);
}

}  // namespace
}  // namespace dc
