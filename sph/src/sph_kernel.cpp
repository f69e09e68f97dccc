#include "dc/sph/sph_kernel.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "dc/core/error.hpp"

namespace dc {

namespace {

constexpr double kPi = std::numbers::pi;

struct KernelName {
  SphKernelType type;
  const char* name;
};
constexpr KernelName kNames[] = {
    {SphKernelType::Poly6, "poly6"},
    {SphKernelType::Spiky, "spiky"},
    {SphKernelType::Cubic, "cubic"},
    {SphKernelType::Poly6Legacy3d, "poly6-legacy3d"},
    {SphKernelType::SpikyLegacy3d, "spiky-legacy3d"},
};

// h^n by repeated multiplication: std::pow's last bit may depend on the CPU's libm variant
// (docs/reproducibility.md); n ≤ 9 products are deterministic under -ffp-contract=off.
double int_pow(double h, int n) {
  double r = 1.0;
  for (int k = 0; k < n; ++k) r *= h;
  return r;
}

// Normalisation constant of each kernel at support h (see the header for the formulas).
double constant_of(SphKernelType type, double h) {
  switch (type) {
    case SphKernelType::Poly6: return 4.0 / (kPi * int_pow(h, 8));
    case SphKernelType::Spiky: return 10.0 / (kPi * int_pow(h, 5));
    case SphKernelType::Cubic: return 40.0 / (7.0 * kPi * h * h);
    case SphKernelType::Poly6Legacy3d: return 315.0 / (64.0 * kPi * int_pow(h, 9));
    case SphKernelType::SpikyLegacy3d: return 15.0 / (kPi * int_pow(h, 6));
  }
  throw InvalidArgument("sph kernel: unknown kernel type");
}

}  // namespace

const char* to_string(SphKernelType type) {
  for (const auto& k : kNames)
    if (k.type == type) return k.name;
  return "unknown";
}

SphKernelType parse_sph_kernel(std::string_view name) {
  for (const auto& k : kNames)
    if (name == k.name) return k.type;
  std::ostringstream os;
  os << "unknown sph kernel '" << name << "' (available:";
  for (const auto& k : kNames) os << ' ' << k.name;
  os << ')';
  throw ConfigError(os.str());
}

std::vector<std::string> sph_kernel_names() {
  std::vector<std::string> out;
  for (const auto& k : kNames) out.emplace_back(k.name);
  return out;
}

SphKernel::SphKernel(SphKernelType type, double h) : type_(type), h_(h), h2_(h * h), c_(0.0) {
  if (!std::isfinite(h) || h <= 0.0) {
    std::ostringstream os;
    os << "sph kernel '" << to_string(type) << "': support radius h = " << h
       << " must be finite and > 0";
    throw InvalidArgument(os.str());
  }
  c_ = constant_of(type, h);
  if (!std::isfinite(c_) || c_ <= 0.0) {
    std::ostringstream os;
    os << "sph kernel '" << to_string(type) << "': support radius h = " << h
       << " makes the normalisation constant overflow or underflow";
    throw InvalidArgument(os.str());
  }
}

SphKernel SphKernel::from_name(std::string_view name, double h) {
  return SphKernel(parse_sph_kernel(name), h);
}

double SphKernel::from_r2(double r2) const {
  if (!(r2 < h2_)) return 0.0;  // also 0 for NaN distances
  switch (type_) {
    case SphKernelType::Poly6:
    case SphKernelType::Poly6Legacy3d: return detail::poly6_r2(c_, h2_, r2);
    case SphKernelType::Spiky:
    case SphKernelType::SpikyLegacy3d: return detail::spiky_r2(c_, h_, r2);
    case SphKernelType::Cubic: return detail::cubic_r2(c_, 1.0 / h_, r2);
  }
  return 0.0;
}

double SphKernel::operator()(double r) const { return from_r2(r * r); }

double SphKernel::plane_integral() const {
  switch (type_) {
    case SphKernelType::Poly6:
    case SphKernelType::Spiky:
    case SphKernelType::Cubic: return 1.0;
    // ∫_0^h (h² − r²)³ 2π r dr = π h⁸/4  ⇒  315/(64π h⁹) · π h⁸/4 = 315/(256 h)
    case SphKernelType::Poly6Legacy3d: return 315.0 / (256.0 * h_);
    // ∫_0^h (h − r)³ 2π r dr = π h⁵/10  ⇒  15/(π h⁶) · π h⁵/10 = 3/(2 h)
    case SphKernelType::SpikyLegacy3d: return 3.0 / (2.0 * h_);
  }
  return 0.0;
}

}  // namespace dc
