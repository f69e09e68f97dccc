#pragma once
// A portable random stream: GSL's mt19937 with GSL's own samplers, so that the same seed
// gives the same numbers on every compiler and standard library (std::*_distribution does
// not). Owned and passed explicitly; there is no global generator.
#include <cstdint>
#include <memory>

#include <gsl/gsl_rng.h>

namespace dc {

class Rng {
 public:
  explicit Rng(std::uint64_t seed);
  ~Rng();
  Rng(Rng&&) noexcept;
  Rng& operator=(Rng&&) noexcept;
  Rng(const Rng&) = delete;
  Rng& operator=(const Rng&) = delete;

  double uniform();                          ///< U[0, 1)
  double uniform(double lo, double hi);      ///< U[lo, hi)
  double gaussian(double sigma);             ///< N(0, σ²) (GSL ziggurat)
  std::uint64_t uniform_int(std::uint64_t n);///< uniform in {0, …, n−1}, n ≥ 1
  [[nodiscard]] gsl_rng* raw() { return rng_.get(); }

 private:
  struct Deleter { void operator()(gsl_rng* r) const; };
  std::unique_ptr<gsl_rng, Deleter> rng_;
};

}  // namespace dc
