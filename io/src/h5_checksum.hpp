#pragma once
// Checksums of the HDF5 layer (docs/formats.md "Checksums"). What HDF5 checks by itself once
// a file uses the 1.10 format (file_access_with_checksums): the superblock, object headers
// (with their attributes and compact datasets), B-trees, heaps of links and the chunk
// indexes carry Jenkins lookup3 checksums; chunked datasets carry Fletcher-32 per chunk (the
// filter this layer adds to every dataset it creates). What it does not check: the global
// heap, where variable-length strings live, and contiguous raw data — so every string
// dataset and every variable-length string attribute this layer writes gets a stored
// FNV-1a hash of its values (an int64 attribute, itself inside a checksummed object header),
// verified on read. Files written without them (older files, h5py) are read unchecked.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dc::h5_detail {

/// Attribute holding the hash of a string dataset's values.
inline constexpr const char* kStringsChecksum = "dc_checksum";
/// Prefix of the attribute holding the hash of the string attribute NAME: "dc_checksum:NAME".
inline constexpr std::string_view kAttributeChecksumPrefix = "dc_checksum:";

inline std::string attribute_checksum_name(std::string_view attribute) {
  return std::string(kAttributeChecksumPrefix) + std::string(attribute);
}

/// True for the names of the checksum attributes (hidden from attribute_names()).
inline bool is_checksum_attribute(std::string_view name) {
  return name == kStringsChecksum || name.substr(0, kAttributeChecksumPrefix.size()) == kAttributeChecksumPrefix;
}

/// FNV-1a (64 bit) over each value's length (8 bytes, little-endian) and bytes. Every step
/// (xor a byte, multiply by an odd prime mod 2^64) is a bijection of the state, so any change
/// of one byte — in particular any single bit flip — changes the result.
inline std::int64_t strings_checksum(const std::vector<std::string>& values) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  const auto mix = [&h](unsigned char byte) { h = (h ^ byte) * 0x100000001b3ull; };
  for (const std::string& v : values) {
    std::uint64_t n = v.size();
    for (int i = 0; i < 8; ++i, n >>= 8) mix(static_cast<unsigned char>(n & 0xffu));
    for (const char c : v) mix(static_cast<unsigned char>(c));
  }
  return static_cast<std::int64_t>(h);
}

/// "…: checksum mismatch: the file is damaged" when HDF5's `reason` says a checksum failed
/// (Fletcher-32 of a chunk, or a metadata checksum), else "".
inline std::string checksum_failure(const std::string& reason) {
  const bool checksum = reason.find("checksum") != std::string::npos || reason.find("Fletcher32") != std::string::npos;
  return checksum ? "checksum mismatch: the file is damaged" : "";
}

}  // namespace dc::h5_detail
