#include "dc/core/rng.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <cstring>
#include <new>

#include "dc/core/error.hpp"

namespace dc {

struct Rng::Generator {
  gsl_rng* r;
  explicit Generator(gsl_rng* rng) : r(rng) {
    if (r == nullptr) throw std::bad_alloc();
  }
  ~Generator() { gsl_rng_free(r); }
  Generator(const Generator&) = delete;
  Generator& operator=(const Generator&) = delete;
};

Rng::Rng(std::uint64_t seed) : gen_(std::make_unique<Generator>(gsl_rng_alloc(gsl_rng_mt19937))) {
  // gsl_rng_set takes an unsigned long; mt19937 uses its low 32 bits. Fold the high half
  // in so that seeds differing only above bit 32 still give different streams.
  gsl_rng_set(gen_->r, static_cast<unsigned long>((seed ^ (seed >> 32)) & 0xffffffffULL));
}
Rng::~Rng() = default;
Rng::Rng(Rng&&) noexcept = default;
Rng& Rng::operator=(Rng&&) noexcept = default;

double Rng::uniform() { return gsl_rng_uniform(gen_->r); }
double Rng::uniform(double lo, double hi) { return lo + (hi - lo) * gsl_rng_uniform(gen_->r); }
double Rng::gaussian(double sigma) { return gsl_ran_gaussian_ziggurat(gen_->r, sigma); }
std::uint64_t Rng::uniform_int(std::uint64_t n) {
  if (n == 0) throw InvalidArgument("Rng::uniform_int: n must be >= 1");
  if (n <= 0xffffffffULL) return gsl_rng_uniform_int(gen_->r, static_cast<unsigned long>(n));
  // Wider ranges: combine two draws (rarely needed; kept exact by rejection).
  const std::uint64_t limit = ~0ULL - (~0ULL % n);
  for (;;) {
    const std::uint64_t hi = gsl_rng_get(gen_->r), lo = gsl_rng_get(gen_->r);
    const std::uint64_t v = (hi << 32) | (lo & 0xffffffffULL);
    if (v < limit) return v % n;
  }
}

std::string Rng::algorithm() const { return gsl_rng_name(gen_->r); }

std::vector<std::uint8_t> Rng::save_state() const {
  const auto* bytes = static_cast<const std::uint8_t*>(gsl_rng_state(gen_->r));
  return {bytes, bytes + gsl_rng_size(gen_->r)};
}

void Rng::restore_state(std::string_view algorithm, std::span<const std::uint8_t> bytes) {
  if (algorithm != gsl_rng_name(gen_->r) || bytes.size() != gsl_rng_size(gen_->r))
    throw InvalidArgument("Rng::restore_state: a " + std::string(algorithm) + " state of " +
                          std::to_string(bytes.size()) + " bytes does not fit this " + gsl_rng_name(gen_->r) +
                          " stream (" + std::to_string(gsl_rng_size(gen_->r)) + " bytes)");
  // GSL's mt19937 state is {unsigned long mt[624]; int mti;}: the words may hold anything
  // (only their low 32 bits are used), but the position mti indexes mt[] and must be in
  // 0..624 (624 = regenerate the block on the next draw).
  constexpr std::size_t kWords = 624;
  if (std::string_view(gsl_rng_name(gen_->r)) == "mt19937") {
    int position = -1;
    if (bytes.size() >= kWords * sizeof(unsigned long) + sizeof(int))
      std::memcpy(&position, bytes.data() + kWords * sizeof(unsigned long), sizeof(int));
    if (position < 0 || position > static_cast<int>(kWords))
      throw InvalidArgument("Rng::restore_state: damaged mt19937 state (position " + std::to_string(position) +
                            " is outside 0..624)");
  }
  std::memcpy(gsl_rng_state(gen_->r), bytes.data(), bytes.size());
}

}  // namespace dc
