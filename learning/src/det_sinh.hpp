#pragma once
// Deterministic, vectorisable sinh of a float: the label expansion G = s·sinh(z) of a model
// with label_scale s > 0 (labels.hpp), evaluated at every node the cnn starter reads back.
// Contract: IEEE 754 add, subtract, multiply, divide and bit operations only, in a fixed
// order (the tree is compiled with -ffp-contract=off), in double: the same bits in every build
// and on every x86-64 CPU, unlike libm's sinhf, and GCC vectorises a loop of it. Taylor series
// for |z| < 1, Cody–Waite eᵃ otherwise, |z| clamped to 90; within ~3·10⁻¹⁶ relative before the
// one rounding to float. NaN → NaN, ±inf → ±inf, ±0 → ±0. Derivation and error bounds:
// docs/learning.md "Deterministic sinh".
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
