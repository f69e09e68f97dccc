// Deterministic sin/cos (det_math.hpp). The reduction and the kernels follow fdlibm's
// e_rem_pio2.c (medium case), k_sin.c and k_cos.c as restated in musl (src/math/__rem_pio2.c,
// __sin.c, __cos.c); the constants are theirs:
//   Copyright (C) 1993 by Sun Microsystems, Inc. All rights reserved.
//   Developed at SunSoft, a Sun Microsystems, Inc. business.
//   Permission to use, copy, modify, and distribute this software is freely granted,
//   provided that this notice is preserved.
// Every expression is evaluated as written (no contraction: -ffp-contract=off for the whole
// tree; SSE2 doubles, no x87 excess precision on x86-64), so the bits are fixed by IEEE 754.
#include "det_math.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

namespace dc {
namespace {

// π/2 = pio2_1 + pio2_2 + pio2_3 + pio2_3t; each of the first three has 33 significant bits,
// so n · pio2_i is exact for |n| < 2²⁰. pio2_it = π/2 − (pio2_1 + … + pio2_i).
constexpr double kInvPio2 = 6.36619772367581382433e-01;  // 0x3FE45F30 6DC9C883
constexpr double kPio2_1 = 1.57079632673412561417e+00;   // 0x3FF921FB 54400000
constexpr double kPio2_1t = 6.07710050650619224932e-11;  // 0x3DD0B461 1A626331
constexpr double kPio2_2 = 6.07710050630396597660e-11;   // 0x3DD0B461 1A600000
constexpr double kPio2_2t = 2.02226624879595063154e-21;  // 0x3BA3198A 2E037073
constexpr double kPio2_3 = 2.02226624871116645580e-21;   // 0x3BA3198A 2E000000
constexpr double kPio2_3t = 8.47842766036889956997e-32;  // 0x397B839A 252049C1
constexpr double kPio4 = 0x1.921fb54442d18p-1;
constexpr double kTwoPi = 0x1.921fb54442d18p+2;  // the double nearest 2π (2.45e-16 below it)
// x + 1.5·2⁵² − 1.5·2⁵² rounds x to the nearest integer (ties to even) for |x| < 2⁵¹.
constexpr double kToInt = 0x1.8p52;

// sin on [−π/4, π/4]: sin(x) ≈ x + S1 x³ + … + S6 x¹³ (|error| < 2^−58.3 relative to the
// polynomial's value, fdlibm); y is the tail of the reduced argument x + y.
constexpr double kS1 = -1.66666666666666324348e-01;  // 0xBFC55555 55555549
constexpr double kS2 = 8.33333333332248946124e-03;   // 0x3F811111 1110F8A6
constexpr double kS3 = -1.98412698298579493134e-04;  // 0xBF2A01A0 19C161D5
constexpr double kS4 = 2.75573137070700676789e-06;   // 0x3EC71DE3 57B1FE7D
constexpr double kS5 = -2.50507602534068634195e-08;  // 0xBE5AE5E6 8A2B9CEB
constexpr double kS6 = 1.58969099521155010221e-10;   // 0x3DE5D93A 5ACFD57C
// cos on [−π/4, π/4]: cos(x) ≈ 1 − x²/2 + C1 x⁴ + … + C6 x¹⁴ (|error| < 2^−58 relative).
constexpr double kC1 = 4.16666666666666019037e-02;   // 0x3FA55555 5555554C
constexpr double kC2 = -1.38888888888741095749e-03;  // 0xBF56C16C 16C15177
constexpr double kC3 = 2.48015872894767294178e-05;   // 0x3EFA01A0 19CB1590
constexpr double kC4 = -2.75573143513906633035e-07;  // 0xBE927E4F 809C52AD
constexpr double kC5 = 2.08757232129817482790e-09;   // 0x3E21EE9E BDB4B1C4
constexpr double kC6 = -1.13596475577881948265e-11;  // 0xBDA8FAE9 BE8838D4

/// Biased binary exponent of x (bits 52..62).
int exponent_bits(double x) { return static_cast<int>((std::bit_cast<std::uint64_t>(x) >> 52) & 0x7ff); }

double kernel_sin(double x, double y) {
  const double z = x * x, w = z * z;
  const double r = kS2 + z * (kS3 + z * kS4) + z * w * (kS5 + z * kS6);
  const double v = z * x;
  if (y == 0) return x + v * (kS1 + z * r);
  return x - ((z * (0.5 * y - v * r) - y) - v * kS1);
}

double kernel_cos(double x, double y) {
  const double z = x * x, w = z * z;
  const double r = z * (kC1 + z * (kC2 + z * kC3)) + w * w * (kC4 + z * (kC5 + z * kC6));
  const double hz = 0.5 * z;
  const double one_minus_hz = 1.0 - hz;
  // 1 − hz rounded, plus what the rounding lost, plus the polynomial and the tail's −x·y.
  return one_minus_hz + (((1.0 - one_minus_hz) - hz) + (z * r - x * y));
}

/// x = n·π/2 + (y0 + y1), |y0| ≤ ~π/4, for finite |x| < 2²⁰·π/2 (Cody–Waite, fdlibm's medium
/// case): each round subtracts n·pio2_i exactly and carries the rounding error into w; a
/// second (third) round runs when the first left fewer than ~37 (~4) significant bits, i.e.
/// when x is within 2⁻¹⁶ (2⁻⁴⁹) relative of a multiple of π/2. Returns n.
int reduce_medium(double x, double& y0, double& y1) {
  double fn = x * kInvPio2 + kToInt - kToInt;
  double r = x - fn * kPio2_1;
  double w = fn * kPio2_1t;  // first round: good to 85 bits
  // Only reachable under directed rounding modes; kept so n always matches |y0| ≤ π/4.
  if (r - w < -kPio4) {
    fn = fn - 1;
    r = x - fn * kPio2_1;
    w = fn * kPio2_1t;
  } else if (r - w > kPio4) {
    fn = fn + 1;
    r = x - fn * kPio2_1;
    w = fn * kPio2_1t;
  }
  y0 = r - w;
  const int ex = exponent_bits(x);
  if (ex - exponent_bits(y0) > 16) {  // second round: good to 118 bits
    double t = r;
    w = fn * kPio2_2;
    r = t - w;
    w = fn * kPio2_2t - ((t - r) - w);
    y0 = r - w;
    if (ex - exponent_bits(y0) > 49) {  // third round: 151 bits, covers every double
      t = r;
      w = fn * kPio2_3;
      r = t - w;
      w = fn * kPio2_3t - ((t - r) - w);
      y0 = r - w;
    }
  }
  y1 = (r - y0) - w;
  return static_cast<int>(fn);
}

/// Quadrant n and the reduced argument y0 + y1 of any finite x.
int reduce(double x, double& y0, double& y1) {
  const double ax = std::abs(x);
  if (ax <= kPio4) {
    y0 = x;
    y1 = 0;
    return 0;
  }
  // 2²⁰·π/2: n · pio2_i stays exact below it. Above, first x mod 2π_d (exact, see header).
  if (!(ax < 0x1.921fb6p+20)) return reduce_medium(std::fmod(x, kTwoPi), y0, y1);
  return reduce_medium(x, y0, y1);
}

// Below 2⁻²⁷, sin x rounds to x (x³/6 < 2⁻⁵⁶·x, under half an ulp of x) and cos x to 1
// (x²/2 < 2⁻⁵⁵, under half the spacing 2⁻⁵³ of the doubles just below 1).
constexpr double kTiny = 0x1p-27;

}  // namespace

double det_sin(double x) {
  if (!std::isfinite(x)) return x - x;  // NaN for ±inf and NaN
  if (std::abs(x) < kTiny) return x;     // keeps the sign of ±0
  double y0 = 0, y1 = 0;
  const int n = reduce(x, y0, y1);
  switch (n & 3) {
    case 0: return kernel_sin(y0, y1);
    case 1: return kernel_cos(y0, y1);
    case 2: return -kernel_sin(y0, y1);
    default: return -kernel_cos(y0, y1);
  }
}

double det_cos(double x) {
  if (!std::isfinite(x)) return x - x;
  if (std::abs(x) < kTiny) return 1.0;
  double y0 = 0, y1 = 0;
  const int n = reduce(x, y0, y1);
  switch (n & 3) {
    case 0: return kernel_cos(y0, y1);
    case 1: return -kernel_sin(y0, y1);
    case 2: return -kernel_cos(y0, y1);
    default: return kernel_sin(y0, y1);
  }
}

void det_sincos(double x, double& s, double& c) {
  if (!std::isfinite(x)) {
    s = c = x - x;
    return;
  }
  if (std::abs(x) < kTiny) {
    s = x;
    c = 1.0;
    return;
  }
  double y0 = 0, y1 = 0;
  const int n = reduce(x, y0, y1);
  const double ks = kernel_sin(y0, y1), kc = kernel_cos(y0, y1);
  switch (n & 3) {
    case 0: s = ks; c = kc; break;
    case 1: s = kc; c = -ks; break;
    case 2: s = -ks; c = -kc; break;
    default: s = -kc; c = ks; break;
  }
}

}  // namespace dc
