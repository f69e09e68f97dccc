#pragma once
// Deterministic sine and cosine for the physics path (docs/reproducibility.md). glibc's libm
// picks CPU-specific sin/cos variants whose last bit differs, so these are libm-free: only IEEE
// adds, subtracts and multiplies in a fixed order (compiled with -ffp-contract=off, so none is
// fused) plus the exact std::fmod — the same bits on every x86-64 CPU and build.
// Algorithm (fdlibm / musl constants and polynomials, unchanged): Cody–Waite reduction
// x = k·π/2 + r, k = round(x·2/π), π/2 in 33-bit parts, r a double-double r₀ + r₁; minimax
// polynomials for sin r, cos r on |r| ≤ π/4; the quadrant k mod 4 picks ±sin r or ±cos r.
// Accuracy < 1 ulp for |x| < 2²⁰·π/2 rad; larger |x| is first reduced exactly modulo 2π_d (the
// double nearest 2π), shifting the angle by ≤ |x|·3.9·10⁻¹⁷ rad. NaN and ±inf give NaN.
// det_sin(x) = −det_sin(−x), det_cos(x) = det_cos(−x) exactly; det_sincos gives the same bits
// as det_sin and det_cos (one reduction). Details: docs/reproducibility.md "Shape scenes".
namespace dc {

/// sin x [x in rad], deterministic (see above).
double det_sin(double x);
/// cos x [x in rad], deterministic (see above).
double det_cos(double x);
/// s = det_sin(x), c = det_cos(x) bit for bit, with one range reduction.
void det_sincos(double x, double& s, double& c);

}  // namespace dc
