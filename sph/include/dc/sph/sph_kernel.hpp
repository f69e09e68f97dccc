#pragma once
// SPH smoothing kernels W(r, h) for the particle → grid transfer (docs/design.md §4,
// docs/sph.md "Kernels: why 2D constants"). The transfer is two-dimensional, so a kernel is
// normalised over the plane: ∫_0^h W(r, h) 2π r dr = 1 (W in 1/m², r and h in m); a grid value
// G = Σ_k W v_k is then a density of v per m². All kernels have support r ≤ h and vanish there:
//   poly6   W = 4/(π h⁸) (h² − r²)³
//   spiky   W = 10/(π h⁵) (h − r)³
//   cubic   W = σ (6q³ − 6q² + 1) for q = r/h ≤ ½, σ 2 (1 − q)³ for ½ < q ≤ 1, σ = 40/(7π h²)
// "poly6-legacy3d" and "spiky-legacy3d" use the three-dimensional constants 315/(64π h⁹) and
// 15/(π h⁶), which do not integrate to 1 over the plane; they are explicitly named study
// options that reproduce the legacy mode (docs/sph.md "The legacy modes"), never a default.
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

namespace dc {

enum class SphKernelType {
  Poly6,           ///< "poly6":  4/(π h⁸)(h² − r²)³
  Spiky,           ///< "spiky":  10/(π h⁵)(h − r)³
  Cubic,           ///< "cubic":  2D cubic B-spline, σ = 40/(7π h²)
  Poly6Legacy3d,   ///< "poly6-legacy3d": 315/(64π h⁹)(h² − r²)³ — WRONG in 2D, study only
  SpikyLegacy3d,   ///< "spiky-legacy3d": 15/(π h⁶)(h − r)³     — WRONG in 2D, study only
};

/// The name used on the command line and in files ("poly6", ..., "spiky-legacy3d").
const char* to_string(SphKernelType type);
/// Inverse of to_string; throws ConfigError listing the valid names for an unknown one.
SphKernelType parse_sph_kernel(std::string_view name);
/// All names, the 2D-normalised ones first.
std::vector<std::string> sph_kernel_names();

/// A kernel type with its support radius h [m]. A small value type: copy it freely.
/// The evaluation is a switch on the type; hot loops (splatting) dispatch once per call
/// on type() and use the per-type functions in detail:: instead.
class SphKernel {
 public:
  /// Throws InvalidArgument unless h is finite and > 0.
  SphKernel(SphKernelType type, double h);
  /// By name (see parse_sph_kernel); throws ConfigError / InvalidArgument.
  static SphKernel from_name(std::string_view name, double h);

  [[nodiscard]] SphKernelType type() const { return type_; }
  [[nodiscard]] double h() const { return h_; }
  [[nodiscard]] const char* name() const { return to_string(type_); }
  /// True for the 3D-constant study options.
  [[nodiscard]] bool is_legacy3d() const {
    return type_ == SphKernelType::Poly6Legacy3d || type_ == SphKernelType::SpikyLegacy3d;
  }

  /// W(r, h) [1/m²] for a distance r ≥ 0 [m]; 0 for r ≥ h.
  [[nodiscard]] double operator()(double r) const;
  /// W as a function of r² (avoids the square root for poly6); 0 for r² ≥ h².
  [[nodiscard]] double from_r2(double r2) const;
  /// W(0, h): the peak value.
  [[nodiscard]] double peak() const { return from_r2(0.0); }
  /// The exact ∫_{R²} W dA: 1 for the 2D kernels, 315/(256 h) and 3/(2 h) for the legacy ones.
  [[nodiscard]] double plane_integral() const;
  /// The normalisation constant in front of the polynomial (e.g. 4/(π h⁸) for poly6).
  [[nodiscard]] double constant() const { return c_; }

 private:
  SphKernelType type_;
  double h_;
  double h2_;
  double c_;  // normalisation constant of the type at this h
};

namespace detail {
// Per-type evaluation from r² with the constant precomputed: used by the splatting loops
// after a single dispatch on the type. h2 = h², inv_h = 1/h. Caller guarantees r2 < h2.
inline double poly6_r2(double c, double h2, double r2) {
  const double t = h2 - r2;
  return c * t * t * t;
}
inline double spiky_r2(double c, double h, double r2) {
  const double t = h - std::sqrt(r2);
  return c * t * t * t;
}
inline double cubic_r2(double c, double inv_h, double r2) {
  const double q = std::sqrt(r2) * inv_h;
  if (q <= 0.5) return c * (6.0 * q * q * (q - 1.0) + 1.0);
  const double t = 1.0 - q;
  return c * 2.0 * t * t * t;
}
}  // namespace detail

}  // namespace dc
