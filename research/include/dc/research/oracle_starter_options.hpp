#pragma once
// The options of dc_research's starters that take an argument, one struct each, parsed in one
// place on dc_warmstart's StarterArgument (same one-line ConfigError as the methods' options;
// the forms are listed in docs/bench.md "Starters and their arguments"):
//   copy[:D]                              CopyStarterOptions     parse_copy_options
//   copy-noise:R                          CopyNoiseOptions       parse_copy_noise_options
//   copy-active[:F|:normal|:friction]     CopyActiveOptions      parse_copy_active_options
//   random[:SEED]                         RandomStarterOptions   parse_random_options
// shared with dc_warmstart (starter_options.hpp): copy-active-cg[:ITER] (parse_cgls_options),
// sph, sph-residual, sph-gain, sph-gain-add [:KERNEL:D:H[:NORM]] (parse_sph_options).
// copy-range and bad take no argument (reject_argument).
#include <cstdint>
#include <optional>

#include "dc/warmstart/starter_options.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

/// copy[:D]: this step's λ*, exactly or rounded to D decimals.
struct CopyStarterOptions {
  bool rounded = false;  ///< copy:D rounds λ* to D decimals; plain copy returns it exactly
  /// D, when rounded: decimals of λ [N], 0..15 (an absolute error ≤ ½·10⁻ᴰ N; beyond 15
  /// decimals a double of a few newtons has no digits left to round).
  int decimals = 0;
};

/// "copy[:D]" with D an integer in 0..15.
CopyStarterOptions parse_copy_options(const WarmStartSpec& spec);

/// copy-noise:R: λ* × (1 + R ξ) per row, ξ ~ N(0, 1) from the run's seed.
struct CopyNoiseOptions {
  double relative = 0;  ///< R ≥ 0 (finite): the relative error; no default, copy-noise needs it
};

/// "copy-noise:R" with R a finite number ≥ 0 (the argument is required).
CopyNoiseOptions parse_copy_noise_options(const WarmStartSpec& spec);

/// Which half of λ*'s active set copy-active takes over builtin-active's.
enum class ActiveSetPart {
  All,       ///< the whole mode (separating, sticking, sliding ±)
  Normal,    ///< only which contacts touch (copy-active:normal)
  Friction,  ///< only stick/slide where both touch (copy-active:friction)
};

/// copy-active[:F|:normal|:friction] (copy_active_warm_starter.cpp).
struct CopyActiveOptions {
  /// F ∈ [0, 1]: the share of the contacts where builtin-active's mode is wrong that get λ*'s
  /// (chosen by a fixed hash of the contact key); 0 is builtin-active, 1 copy-active.
  double share = 1.0;
  ActiveSetPart part = ActiveSetPart::All;  ///< which half of λ*'s modes is used
};

/// "copy-active[:F|:normal|:friction]" with 0 <= F <= 1 (normal and friction keep share = 1).
CopyActiveOptions parse_copy_active_options(const WarmStartSpec& spec);

/// random[:SEED]: the negative control's random stream.
struct RandomStarterOptions {
  std::optional<std::uint64_t> seed;  ///< SEED; none: the run's seed (WarmStartEnv::seed)
};

/// "random[:SEED]" with SEED an unsigned 64-bit integer.
RandomStarterOptions parse_random_options(const WarmStartSpec& spec);

}  // namespace dc
