#pragma once
// Byte-for-byte comparison for the bit-equality tests (same bits: ±0 and NaN payloads told apart).
#include <cstddef>
#include <cstring>

namespace dc::test {

/// True when the `n` objects at `a` and `b` have the same bytes. With n = 0 it is true without
/// reading either pointer: an empty container's data() may be null, and memcmp must not be given a
/// null pointer even for zero bytes (UndefinedBehaviorSanitizer stops the suite on it).
template <class T>
bool bytes_equal(const T* a, const T* b, std::size_t n) {
  return n == 0 || std::memcmp(a, b, n * sizeof(T)) == 0;
}

/// The same for two containers with data() and size() (std::vector, Eigen vectors): equal sizes
/// and equal bytes.
template <class C>
bool bytes_equal(const C& a, const C& b) {
  return a.size() == b.size() && bytes_equal(a.data(), b.data(), static_cast<std::size_t>(a.size()));
}

}  // namespace dc::test
