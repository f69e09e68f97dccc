#pragma once
// Flipping random bits of an HDF5 file and reading everything back (h5_dump.hpp): each flip
// is detected (the reader throws), harmless (every value reads back unchanged: the bit was in
// unused space) or silent (a value changed and nothing said so — what checksums must prevent).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/h5_dump.hpp"

namespace dc::test {

struct BitFlipCounts {
  int detected = 0;
  int harmless = 0;
  int silent = 0;
  std::vector<std::string> silent_bits;  ///< "byte B bit K" of each silent flip
  std::string first_error;               ///< the message of the first detected flip
  /// Flips after which HDF5 still held open objects (h5_open_object_count() > 0): libhdf5
  /// could not close the damaged file (HDF5 then reports "infinite loop closing library").
  std::vector<std::string> leaked_bits;
};

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

/// `flips` flips of one uniformly drawn bit each (a fresh copy of `file` each time, written
/// to `scratch`), drawn from a std::mt19937_64 seeded with `seed`.
inline BitFlipCounts flip_random_bits(const std::string& file, int flips, std::uint64_t seed,
                                      const std::string& scratch) {
  const std::string original = read_bytes(file);
  const std::string reference = dump_h5(file);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::uint64_t> bit(0, 8 * static_cast<std::uint64_t>(original.size()) - 1);
  BitFlipCounts n;
  for (int i = 0; i < flips; ++i) {
    const std::uint64_t b = bit(rng);
    std::string damaged = original;
    damaged[b / 8] = static_cast<char>(damaged[b / 8] ^ (1 << (b % 8)));
    write_bytes(scratch, damaged);
    try {
      if (dump_h5(scratch) == reference) {
        ++n.harmless;
      } else {
        ++n.silent;
        n.silent_bits.push_back("byte " + std::to_string(b / 8) + " bit " + std::to_string(b % 8));
      }
    } catch (const std::exception& e) {
      if (n.detected++ == 0) n.first_error = e.what();
    }
    if (h5_open_object_count() > 0)
      n.leaked_bits.push_back("byte " + std::to_string(b / 8) + " bit " + std::to_string(b % 8));
  }
  std::filesystem::remove(scratch);
  return n;
}

}  // namespace dc::test
