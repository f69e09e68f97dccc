#include "dc/engine/rng.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "dc/engine/error.hpp"

namespace dc {

void Rng::Deleter::operator()(gsl_rng* r) const { gsl_rng_free(r); }

Rng::Rng(std::uint64_t seed) : rng_(gsl_rng_alloc(gsl_rng_mt19937)) {
  if (!rng_) throw std::bad_alloc();
  // gsl_rng_set takes an unsigned long; mt19937 uses its low 32 bits. Fold the high half
  // in so that seeds differing only above bit 32 still give different streams.
  gsl_rng_set(rng_.get(), static_cast<unsigned long>((seed ^ (seed >> 32)) & 0xffffffffULL));
}
Rng::~Rng() = default;
Rng::Rng(Rng&&) noexcept = default;
Rng& Rng::operator=(Rng&&) noexcept = default;

double Rng::uniform() { return gsl_rng_uniform(rng_.get()); }
double Rng::uniform(double lo, double hi) { return lo + (hi - lo) * gsl_rng_uniform(rng_.get()); }
double Rng::gaussian(double sigma) { return gsl_ran_gaussian_ziggurat(rng_.get(), sigma); }
std::uint64_t Rng::uniform_int(std::uint64_t n) {
  if (n == 0) throw InvalidArgument("Rng::uniform_int: n must be >= 1");
  if (n <= 0xffffffffULL) return gsl_rng_uniform_int(rng_.get(), static_cast<unsigned long>(n));
  // Wider ranges: combine two draws (rarely needed; kept exact by rejection).
  const std::uint64_t limit = ~0ULL - (~0ULL % n);
  for (;;) {
    const std::uint64_t hi = gsl_rng_get(rng_.get()), lo = gsl_rng_get(rng_.get());
    const std::uint64_t v = (hi << 32) | (lo & 0xffffffffULL);
    if (v < limit) return v % n;
  }
}

}  // namespace dc
