#pragma once
// The options of this library's starters that take an argument, one struct each, and the one
// place their command-line forms are parsed (on StarterArgument, starter_argument.hpp). A
// factory calls its parser and builds the starter from the struct; docs/bench.md "Starters and
// their arguments" lists the same forms. The starters without options (zero, builtin,
// builtin-extrapolate, builtin-statics, builtin-active) refuse any argument (reject_argument).
//
//   builtin-coarse[:D[:ITER]]          CoarseStarterOptions  parse_coarse_options
//   builtin-active-cg[:ITER]           CglsStarterOptions    parse_cgls_options (also copy-active-cg)
//   gate:INNER, gate-l2:INNER          GateOptions           parse_gate_options
//   sph-prev[:KERNEL:D:H[:NORM]],      SphTransferDef        parse_sph_options (also dc_research's
//   builtin-gain-extrapolate[:…]                               sph, sph-residual, sph-gain, sph-gain-add)
#include <string>

#include "dc/sph/sph_transfer.hpp"
#include "dc/warmstart/starter_argument.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

/// builtin-coarse[:D[:ITER]] (coarse_warm_starter.cpp): the Galerkin coarse-grid correction.
struct CoarseStarterOptions {
  double spacing = 1.0;  ///< D [m] > 0: node spacing of the gain grid
  int iterations = 30;   ///< ITER ≥ 1: conjugate-gradient iterations on (Pᵀ A P) g = −Pᵀ (A λ_b + b)
};

/// D and ITER of "builtin-coarse[:D[:ITER]]"; the defaults for what is left out.
CoarseStarterOptions parse_coarse_options(const WarmStartSpec& spec);

/// NAME[:ITER] of the matrix-free active-set solves builtin-active-cg and (dc_research)
/// copy-active-cg (solve_on_active_set_cgls).
struct CglsStarterOptions {
  int iterations = 100;  ///< ITER ≥ 1: CGLS steps of the minimum-norm solve (two A products each)
};

/// ITER of "NAME[:ITER]"; 100 without an argument.
CglsStarterOptions parse_cgls_options(const WarmStartSpec& spec);

/// How a gate scores a guess: the natural-map residual's max norm (the solver's θ measure) or
/// its 2-norm (the whole error, not its worst contact).
enum class GateNorm { Max, L2 };

/// gate:INNER and gate-l2:INNER (gate_warm_starter.cpp): INNER's guess or builtin's, whichever
/// has the smaller residual.
struct GateOptions {
  std::string inner;              ///< INNER: the gated starter's spec, any starter but a gate
  GateNorm norm = GateNorm::Max;  ///< gate: Max; gate-l2: L2 (the norm is in the name)
};

/// INNER from the argument (required; a gate of a gate is refused: the inner gate already
/// falls back to builtin, so the outer one would only score the same two guesses again) and
/// the norm from the name. InvalidArgument when spec.name is neither
/// "gate" nor "gate-l2" (a factory registered under another name).
GateOptions parse_gate_options(const WarmStartSpec& spec);

/// The SPH setting of a grid starter, "NAME[:KERNEL:D:H[:NORM]]": default_sph_setting on a
/// 30 × 30 box (poly6, d = 0.5 m, h = 0.355 m, Shepard read-back; the starter replaces the box
/// by the scene's) with parse_sph_setting applied to the argument. KERNEL is one of
/// sph_kernel_names(), D and H are > 0 [m], NORM is shepard, none or
/// sum-to-one-legacy (alias legacy).
/// Its ConfigError names the starter's spec and carries parse_sph_setting's reason.
SphTransferDef parse_sph_options(const WarmStartSpec& spec);

}  // namespace dc
