#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the choice of the kernels of one ISA
// (scalar, AVX2, AVX-512) for the sweeps over single-contact batches (full or compact layout) and
// pair batches and for the closing packed residual, and the call of the right one for a range
// of batches. PgsColoredKernel::Auto resolves to pgs_colored_auto_kernel().
#include "dc/lcp/pgs_colored.hpp"
#include "solvers/pgs_colored/compact/compact_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"
#include "solvers/pgs_colored/residual/packed_residual.hpp"

namespace dc::colored {

/// k, or the automatic choice for Auto; throws InvalidArgument when k is not available on this
/// CPU (pgs_colored_kernel_available).
PgsColoredKernel resolve(PgsColoredKernel k);

/// The kernels of one ISA: single-contact batches and two-point manifold batches, and the
/// closing residual's (residual/packed_residual.hpp).
struct Kernels {
  SweepKernel single;
  PairKernel pairs;
  ResidualKernels residual;
  CompactKernel compact;  // single-contact batches in the compact layout
};

/// The kernels of a resolved (not Auto) choice.
Kernels kernel_fn(PgsColoredKernel k);

/// Batches [lo, hi) of range rg with the kernel of its kind (pair batches' λ from pair_base;
/// single batches compact when prep.compact_on).
inline void run_range(const Prepared& prep, const Kernels& kern, const Range& rg, int lo, int hi, const double* in,
                      double* out, double* u, Acc& acc) {
  if (rg.pairs)
    kern.pairs(prep.pairs.data(), lo, hi, in + prep.pair_base, out + prep.pair_base, u, acc);
  else if (prep.compact_on)
    kern.compact(prep.compact.data(), lo, hi, in, out, u, acc);
  else
    kern.single(prep.batches.data(), lo, hi, in, out, u, acc);
}

}  // namespace dc::colored
