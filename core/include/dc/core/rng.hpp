#pragma once
// A portable random stream: GSL's mt19937 with GSL's own samplers, so that the same seed
// gives the same numbers on every compiler and standard library (std::*_distribution does
// not). Owned and passed explicitly; there is no global generator.
//
// GSL is a PRIVATE dependency of dc_engine: the generator lives behind an opaque pointer,
// and a stream is checkpointed through save_state()/restore_state() (e.g. the trainer's
// resume state), never through GSL calls of the user.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

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

  /// Name of the generator algorithm, stored next to a saved state ("mt19937").
  [[nodiscard]] std::string algorithm() const;
  /// The generator's complete state (GSL's state block, byte for byte: 5 000 bytes for
  /// mt19937 on LP64; machine-dependent, like any checkpoint of this process). After
  /// restore_state(algorithm(), bytes) the stream continues exactly as from here.
  [[nodiscard]] std::vector<std::uint8_t> save_state() const;
  /// Continues the stream from a state saved by save_state(). InvalidArgument (one line)
  /// when `algorithm` is not this generator's, `bytes` has another size, or the state's
  /// position in its block is out of range (a damaged checkpoint; it would read outside it).
  void restore_state(std::string_view algorithm, std::span<const std::uint8_t> bytes);

 private:
  struct Generator;  // owns the gsl_rng (defined in rng.cpp)
  std::unique_ptr<Generator> gen_;
};

}  // namespace dc
