// The whole-file hash trailer of sealed HDF5 files (h5_file_hash.hpp).
#include "h5_file_hash.hpp"

#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <vector>

#include "dc/core/error.hpp"

namespace dc::h5_detail {
namespace {

constexpr std::string_view kMagic = "DCFHASH1";
constexpr std::size_t kTrailerBytes = 24;  // magic, length, hash

/// FNV-1a 64 (the string checksums' hash, h5_checksum.hpp) over a stream of chunks.
struct Fnv1a {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void add(const char* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(p[i])) * 0x100000001b3ull;
  }
};

void put_u64(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i, v >>= 8) out.push_back(static_cast<char>(v & 0xffu));
}

std::uint64_t get_u64(const char* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
  return v;
}

struct Trailer {
  bool present = false;
  std::uint64_t file_size = 0, length = 0, hash = 0;
};

Trailer read_trailer(const std::string& path, std::ifstream& in) {
  Trailer t;
  std::error_code ec;
  t.file_size = std::filesystem::file_size(path, ec);
  if (ec || t.file_size < kTrailerBytes) return t;
  std::array<char, kTrailerBytes> b{};
  in.seekg(static_cast<std::streamoff>(t.file_size - kTrailerBytes));
  if (!in.read(b.data(), b.size())) return t;
  if (std::string_view(b.data(), kMagic.size()) != kMagic) return t;
  t.present = true;
  t.length = get_u64(b.data() + 8);
  t.hash = get_u64(b.data() + 16);
  return t;
}

}  // namespace

std::string with_file_hash(std::string image) {
  Fnv1a f;
  f.add(image.data(), image.size());
  const std::uint64_t length = image.size();
  image.append(kMagic);
  put_u64(image, length);
  put_u64(image, f.h);
  return image;
}

bool verify_file_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;  // the open that follows names the problem
  const Trailer t = read_trailer(path, in);
  if (!t.present) return false;
  const std::string damaged = path + ": checksum mismatch: the file is damaged (";
  if (t.length != t.file_size - kTrailerBytes)
    throw IoError(damaged + "its whole-file hash covers " + std::to_string(t.length) + " bytes, the file has " +
                  std::to_string(t.file_size - kTrailerBytes) + ")");
  in.seekg(0);
  Fnv1a f;
  std::vector<char> buf(std::size_t{1} << 20);
  for (std::uint64_t left = t.length; left > 0;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left, buf.size()));
    if (!in.read(buf.data(), static_cast<std::streamsize>(n))) throw IoError(path + ": cannot read the file to check its hash");
    f.add(buf.data(), n);
    left -= n;
  }
  if (f.h != t.hash) throw IoError(damaged + "whole-file hash differs)");
  return true;
}

void drop_file_hash(const std::string& path) {
  if (!verify_file_hash(path)) return;
  std::error_code ec;
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - kTrailerBytes, ec);
  if (ec) throw IoError(path + ": cannot remove its whole-file hash before writing: " + ec.message());
}

}  // namespace dc::h5_detail
