// SPH kernels: 2D normalisation (∫ W dA = 1 over the plane) by two independent quadratures,
// the legacy 3D constants failing it, shape properties, names and validation.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "dc/core/error.hpp"
#include "dc/sph/sph_kernel.hpp"

namespace dc {
namespace {

constexpr SphKernelType k2d[] = {SphKernelType::Poly6, SphKernelType::Spiky, SphKernelType::Cubic};
constexpr SphKernelType kLegacy[] = {SphKernelType::Poly6Legacy3d, SphKernelType::SpikyLegacy3d};

// ∫_0^h W(r) 2π r dr by the midpoint rule (error O(n⁻²)).
double polar_integral(const SphKernel& w, int n = 200000) {
  const double dr = w.h() / n;
  double s = 0.0;
  for (int k = 0; k < n; ++k) {
    const double r = (k + 0.5) * dr;
    s += w(r) * r;
  }
  return s * 2.0 * std::numbers::pi * dr;
}

// ∫∫ W(|(x, y)|) dx dy over [−h, h]² by the midpoint rule on an m × m Cartesian grid
// (independent of the radial formula: catches a wrong r vs r² handling).
double cartesian_integral(const SphKernel& w, int m = 1200) {
  const double h = w.h();
  const double dx = 2.0 * h / m;
  double s = 0.0;
  for (int j = 0; j < m; ++j) {
    const double y = -h + (j + 0.5) * dx;
    for (int i = 0; i < m; ++i) {
      const double x = -h + (i + 0.5) * dx;
      s += w.from_r2(x * x + y * y);
    }
  }
  return s * dx * dx;
}

TEST(SphKernel, TwoDimensionalKernelsIntegrateToOneOverThePlane) {
  for (const auto type : k2d) {
    for (const double h : {0.25, 0.5, 1.0, 2.3}) {
      const SphKernel w(type, h);
      SCOPED_TRACE(std::string(w.name()) + " h=" + std::to_string(h));
      EXPECT_NEAR(polar_integral(w), 1.0, 1e-6);
      EXPECT_NEAR(cartesian_integral(w), 1.0, 1e-3);
      EXPECT_DOUBLE_EQ(w.plane_integral(), 1.0);
    }
  }
}

TEST(SphKernel, Legacy3dConstantsDoNotIntegrateToOneInTwoDimensions) {
  for (const auto type : kLegacy) {
    for (const double h : {0.25, 0.5, 1.0}) {
      const SphKernel w(type, h);
      SCOPED_TRACE(std::string(w.name()) + " h=" + std::to_string(h));
      const double integral = polar_integral(w);
      EXPECT_NEAR(cartesian_integral(w), integral, 1e-3 * integral);
      // The documented closed forms 315/(256 h) and 3/(2 h) ...
      EXPECT_NEAR(integral, w.plane_integral(), 1e-6 * w.plane_integral());
      // ... are not 1: off by more than 20 % at every seed-like h.
      EXPECT_GT(std::abs(integral - 1.0), 0.2);
      EXPECT_TRUE(w.is_legacy3d());
    }
  }
  EXPECT_NEAR(SphKernel(SphKernelType::Poly6Legacy3d, 0.5).plane_integral(), 315.0 / 128.0, 1e-15);
  EXPECT_NEAR(SphKernel(SphKernelType::SpikyLegacy3d, 0.5).plane_integral(), 3.0, 1e-15);
}

TEST(SphKernel, ConstantsMatchTheDocumentedFormulas) {
  const double pi = std::numbers::pi;
  const double h = 0.5;
  EXPECT_NEAR(SphKernel(SphKernelType::Poly6, h).peak(), 4.0 / (pi * std::pow(h, 8)) * std::pow(h, 6), 1e-12);
  EXPECT_NEAR(SphKernel(SphKernelType::Spiky, h).peak(), 10.0 / (pi * std::pow(h, 5)) * std::pow(h, 3), 1e-12);
  EXPECT_NEAR(SphKernel(SphKernelType::Cubic, h).peak(), 40.0 / (7.0 * pi * h * h), 1e-12);
  EXPECT_NEAR(SphKernel(SphKernelType::Poly6Legacy3d, h).peak(), 315.0 / (64.0 * pi * std::pow(h, 9)) * std::pow(h, 6), 1e-9);
  EXPECT_NEAR(SphKernel(SphKernelType::SpikyLegacy3d, h).peak(), 15.0 / (pi * std::pow(h, 6)) * std::pow(h, 3), 1e-9);
}

TEST(SphKernel, CompactNonNegativeNonIncreasingAndContinuous) {
  for (const auto type : {SphKernelType::Poly6, SphKernelType::Spiky, SphKernelType::Cubic,
                          SphKernelType::Poly6Legacy3d, SphKernelType::SpikyLegacy3d}) {
    const SphKernel w(type, 0.7);
    SCOPED_TRACE(w.name());
    EXPECT_EQ(w(0.7), 0.0);
    EXPECT_EQ(w(0.7000001), 0.0);
    EXPECT_EQ(w(5.0), 0.0);
    EXPECT_NEAR(w(0.7 * (1 - 1e-9)), 0.0, 1e-12 * w.peak());
    double prev = w.peak();
    for (int k = 1; k <= 1000; ++k) {
      const double v = w(0.7 * k / 1000.0);
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, prev + 1e-12 * w.peak());
      EXPECT_LE(prev - v, 0.02 * w.peak());  // no jumps (cubic's two branches meet at q = ½)
      prev = v;
    }
    EXPECT_EQ(w.from_r2(0.49 * 0.49), w(0.49));
  }
}

TEST(SphKernel, NamesRoundTripAndUnknownNamesAreConfigErrors) {
  for (const auto& name : sph_kernel_names()) {
    const SphKernel w = SphKernel::from_name(name, 0.5);
    EXPECT_EQ(std::string(w.name()), name);
    EXPECT_EQ(parse_sph_kernel(name), w.type());
  }
  EXPECT_EQ(sph_kernel_names().front(), "poly6");
  EXPECT_THROW(parse_sph_kernel("gaussian"), ConfigError);
  EXPECT_THROW(parse_sph_kernel(""), ConfigError);
  EXPECT_THROW(parse_sph_kernel("Poly6"), ConfigError);
}

TEST(SphKernel, InvalidSupportRadiusThrows) {
  for (const double h : {0.0, -0.5, std::nan(""), double(INFINITY), -double(INFINITY), 1e-300})
    EXPECT_THROW(SphKernel(SphKernelType::Poly6, h), InvalidArgument) << h;
  EXPECT_THROW(SphKernel::from_name("spiky", 0.0), InvalidArgument);
  EXPECT_NO_THROW(SphKernel(SphKernelType::Spiky, 1e-3));
}

}  // namespace
}  // namespace dc
