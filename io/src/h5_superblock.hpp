#pragma once
// The superblock checksum of an in-memory file's image. Files of the 1.10 format (what this
// layer writes, h5_checksum.hpp) start with a version-2/3 superblock protected by a Jenkins
// lookup3 checksum. H5Fget_file_image (libhdf5 1.10.8) clears the "open for writing" flags in
// the copy it returns but leaves the checksum computed with them set, so the image of a file
// still open — AtomicH5File's — would be refused as damaged; recompute it.
#include <cstddef>
#include <cstdint>
#include <string>

namespace dc::h5_detail {

/// Bob Jenkins' lookup3 hashlittle, byte-wise, as HDF5 uses it for metadata (initval 0).
inline std::uint32_t lookup3(const unsigned char* k, std::size_t length) {
  const auto rot = [](std::uint32_t x, int r) { return (x << r) ^ (x >> (32 - r)); };
  std::uint32_t a, b, c;
  a = b = c = 0xdeadbeefu + static_cast<std::uint32_t>(length);
  const auto word = [&](std::size_t i, std::size_t n) {  // little-endian, n ≤ 4 bytes
    std::uint32_t w = 0;
    for (std::size_t j = 0; j < n; ++j) w |= static_cast<std::uint32_t>(k[i + j]) << (8 * j);
    return w;
  };
  while (length > 12) {
    a += word(0, 4), b += word(4, 4), c += word(8, 4);
    a -= c, a ^= rot(c, 4), c += b, b -= a, b ^= rot(a, 6), a += c;
    c -= b, c ^= rot(b, 8), b += a, a -= c, a ^= rot(c, 16), c += b;
    b -= a, b ^= rot(a, 19), a += c, c -= b, c ^= rot(b, 4), b += a;
    length -= 12, k += 12;
  }
  if (length == 0) return c;
  a += word(0, length < 4 ? length : 4);
  if (length > 4) b += word(4, length < 8 ? length - 4 : 4);
  if (length > 8) c += word(8, length - 8);
  c ^= b, c -= rot(b, 14), a ^= c, a -= rot(c, 11), b ^= a, b -= rot(a, 25);
  c ^= b, c -= rot(b, 16), a ^= c, a -= rot(c, 4), b ^= a, b -= rot(a, 14);
  c ^= b, c -= rot(b, 24);
  return c;
}

/// Rewrites the checksum of a version-2/3 superblock at the start of `image` (8-byte offsets:
/// signature 8, version, offset and length sizes, flags, four addresses → 44 bytes, then the
/// checksum). Leaves other images (superblock version 0/1, other offset sizes) alone.
inline void fix_superblock_checksum(std::string& image) {
  constexpr std::size_t kSigned = 12;  // signature, version, size of offsets/lengths, flags
  if (image.size() < kSigned || (image[8] != 2 && image[8] != 3)) return;
  const std::size_t offsets = static_cast<unsigned char>(image[9]);
  const std::size_t covered = kSigned + 4 * offsets;
  if (image.size() < covered + 4) return;
  const std::uint32_t sum = lookup3(reinterpret_cast<const unsigned char*>(image.data()), covered);
  for (std::size_t j = 0; j < 4; ++j) image[covered + j] = static_cast<char>((sum >> (8 * j)) & 0xffu);
}

}  // namespace dc::h5_detail
