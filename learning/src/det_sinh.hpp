#pragma once
// Deterministic, vectorisable sinh of a float: the label expansion G = s·sinh(z) of a model
// with label_scale s > 0 (labels.hpp), evaluated at every node the cnn starter reads back.
//
// Why not std::sinh(float): glibc's sinhf (via expm1f) costs ~10 ns a call and is an opaque
// libm call, so the ~1,500 expansions per warm start on the seed pile cannot be vectorised
// (half of the read-back's time), and libm may choose CPU-specific variants at load time.
// This version uses only IEEE 754 add, subtract, multiply, divide and bit operations in a
// fixed order (the tree is compiled with -ffp-contract=off, so none is fused), in double:
// it returns the same bits in every build (native, portable, with or without FMA) and on
// every x86-64 CPU, and GCC vectorises a loop of it (AVX-512: 8 lanes).
//
// Algorithm, with a = |z| in double and the sign restored at the end (sinh is odd):
//   * a < 1: the Taylor series a + a³/3! + … + a¹⁷/17!; the first omitted term
//     a¹⁹/19! < 8.3·10⁻¹⁸ relative.
//   * a ≥ 1: E = eᵃ by Cody–Waite reduction a = k·ln2 + r, |r| ≤ ln2/2 (k = round(a/ln2)
//     by the 1.5·2⁵² shift, ln2 split into a 32-bit head, so k·ln2_hi is exact, and a tail),
//     eʳ by its Taylor series to r¹³/13! (omitted r¹⁴/14! < 4.3·10⁻¹⁸), 2ᵏ built from the
//     exponent bits; then sinh a = (E − 1/E)/2, where the subtraction loses < 1.3 bits.
//     a is clamped to 90 first: sinh 90 = 6.1·10³⁸ > FLT_MAX, so every a ≥ 89.42 becomes
//     ±inf when rounded to float, as sinhf does, and eᵃ never overflows the double.
// The double result is within ~3·10⁻¹⁶ relative of sinh z, so its one rounding to float is
// the correctly rounded sinhf(z) unless sinh z lies within that distance of a midpoint
// between two floats (glibc's sinhf itself is not correctly rounded: the two can differ in
// the last bit). NaN gives NaN, ±inf gives ±inf, ±0 gives ±0.
#include <bit>
#include <cmath>
#include <cstdint>

namespace dc::detail {

inline float det_sinhf(float z) {
  const double x = static_cast<double>(z);
  const double a0 = x < 0 ? -x : x;
  const double a = a0 > 90.0 ? 90.0 : a0;  // NaN stays NaN (the comparison is false)

  // a < 1: odd Taylor series in Horner form over a².
  const double a2 = a * a;
  double p = 1.0 / 355687428096000.0;          // 1/17!
  p = p * a2 + 1.0 / 1307674368000.0;           // 1/15!
  p = p * a2 + 1.0 / 6227020800.0;              // 1/13!
  p = p * a2 + 1.0 / 39916800.0;                // 1/11!
  p = p * a2 + 1.0 / 362880.0;                  // 1/9!
  p = p * a2 + 1.0 / 5040.0;                    // 1/7!
  p = p * a2 + 1.0 / 120.0;                     // 1/5!
  p = p * a2 + 1.0 / 6.0;                       // 1/3!
  const double small = a + a * (a2 * p);

  // a ≥ 1: eᵃ = 2ᵏ·eʳ.
  constexpr double kInvLn2 = 1.4426950408889634;      // 1/ln 2
  constexpr double kLn2Hi = 0x1.62e42fee00000p-1;      // ln 2, upper 32 bits (k·kLn2Hi exact, k < 2²⁰)
  constexpr double kLn2Lo = 0x1.a39ef35793c76p-33;     // ln 2 − kLn2Hi
  constexpr double kShift = 0x1.8p52;                  // adding it rounds to an integer
  const double t = a * kInvLn2 + kShift;
  const double k = t - kShift;
  const double r = (a - k * kLn2Hi) - k * kLn2Lo;
  double q = 1.0 / 6227020800.0;  // 1/13!
  q = q * r + 1.0 / 479001600.0;  // 1/12!
  q = q * r + 1.0 / 39916800.0;   // 1/11!
  q = q * r + 1.0 / 3628800.0;    // 1/10!
  q = q * r + 1.0 / 362880.0;     // 1/9!
  q = q * r + 1.0 / 40320.0;      // 1/8!
  q = q * r + 1.0 / 5040.0;       // 1/7!
  q = q * r + 1.0 / 720.0;        // 1/6!
  q = q * r + 1.0 / 120.0;        // 1/5!
  q = q * r + 1.0 / 24.0;         // 1/4!
  q = q * r + 1.0 / 6.0;          // 1/3!
  q = q * r + 0.5;                // 1/2!
  const double er = 1.0 + (r + r * (r * q));
  // t's low mantissa bits hold k (0 ≤ k ≤ 130): 2ᵏ has the biased exponent k + 1023.
  const double two_k = std::bit_cast<double>((std::bit_cast<std::uint64_t>(t) + 1023u) << 52);
  const double e = er * two_k;
  const double large = 0.5 * (e - 1.0 / e);

  const double s = a < 1.0 ? small : large;
  return static_cast<float>(std::copysign(s, x));
}

}  // namespace dc::detail
