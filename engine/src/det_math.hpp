#pragma once
// Deterministic sine and cosine for the physics path (docs/reproducibility.md).
//
// glibc's libm picks CPU-specific variants of sin/cos at load time (FMA/AVX2 vs SSE2 code)
// whose last bit differs for some inputs, so a shape scene stepped with std::sin/std::cos is
// not bit-equal between CPUs (or under GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA). These
// functions are libm-free: every operation is an IEEE 754 add, subtract or multiply in a fixed
// order (the tree is compiled with -ffp-contract=off, so none is fused), plus std::fmod (exact
// by definition) for huge arguments. So they return the same bits on every x86-64 CPU and in
// every build (native or -DDC_NATIVE=OFF).
//
// Algorithm (fdlibm / musl, Sun Microsystems' freely distributable code, whose constants and
// polynomials are used here unchanged):
//   * range reduction x = k·π/2 + r, |r| ≤ ~π/4, k = round(x · 2/π), by Cody–Waite with π/2
//     split into 33-bit parts (k · part is exact for |k| < 2²⁰); r is kept as a double-double
//     r₀ + r₁ (up to three rounds when x lies close to a multiple of π/2: good to 151 bits);
//   * sin r and cos r by fixed minimax polynomials on |r| ≤ π/4 (degree 13 and 14), written
//     for the tail r₁;
//   * the quadrant k mod 4 picks ±sin r or ±cos r.
// Accuracy: < 1 ulp for |x| < 2²⁰·π/2 ≈ 1.65·10⁶ rad (fdlibm's bound; measured against
// long-double sinl/cosl: max 0.78 ulp over 2.6·10⁶ inputs, docs/reproducibility.md). For
// larger |x| the argument is first reduced exactly modulo 2π_d, the double nearest 2π
// (std::fmod is exact by IEEE 754), which shifts the angle by q·(2π − 2π_d) ≤ |x| · 3.9·10⁻¹⁷
// rad (q = |x| div 2π_d; 2π − 2π_d = 2.45·10⁻¹⁶): still deterministic, and no rigid body's
// angle in a simulation reaches 10⁶ rad. NaN and ±inf give NaN.
//
// det_sin(x) = −det_sin(−x), det_cos(x) = det_cos(−x) exactly; det_sincos gives the same bits
// as det_sin and det_cos (one reduction).
namespace dc {

/// sin x [x in rad], deterministic (see above).
double det_sin(double x);
/// cos x [x in rad], deterministic (see above).
double det_cos(double x);
/// s = det_sin(x), c = det_cos(x) bit for bit, with one range reduction.
void det_sincos(double x, double& s, double& c);

}  // namespace dc
