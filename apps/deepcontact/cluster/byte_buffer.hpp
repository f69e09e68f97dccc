#pragma once
// Packing plain values, vectors and strings into one byte buffer for an MPI message
// (comm.hpp) and reading them back in the same order. Both ranks run the same binary, so
// the layout is native (no endianness or padding conversion).
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "cluster/comm.hpp"
#include "dc/core/error.hpp"

namespace dc::cli {

class ByteWriter {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    append(&v, sizeof(T));
  }
  template <class T>
  void put(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(static_cast<std::uint64_t>(v.size()));
    append(v.data(), v.size() * sizeof(T));
  }
  void put(const std::string& s) {
    put(static_cast<std::uint64_t>(s.size()));
    append(s.data(), s.size());
  }
  [[nodiscard]] Bytes take() { return std::move(out_); }

 private:
  void append(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  Bytes out_;
};

class ByteReader {
 public:
  explicit ByteReader(const Bytes& in) : in_(in) {}
  template <class T>
  void get(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    copy(&v, sizeof(T));
  }
  template <class T>
  void get(std::vector<T>& v) {
    std::uint64_t n = 0;
    get(n);
    if (n > (in_.size() - pos_) / sizeof(T)) throw IoError("MPI message: truncated vector");
    v.resize(static_cast<std::size_t>(n));
    copy(v.data(), v.size() * sizeof(T));
  }
  void get(std::string& s) {
    std::uint64_t n = 0;
    get(n);
    if (n > in_.size() - pos_) throw IoError("MPI message: truncated string");
    s.assign(reinterpret_cast<const char*>(in_.data() + pos_), static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
  }
  [[nodiscard]] bool done() const { return pos_ == in_.size(); }

 private:
  void copy(void* p, std::size_t n) {
    if (n > in_.size() - pos_) throw IoError("MPI message: truncated");
    if (n > 0) std::memcpy(p, in_.data() + pos_, n);
    pos_ += n;
  }
  const Bytes& in_;
  std::size_t pos_ = 0;
};

}  // namespace dc::cli
