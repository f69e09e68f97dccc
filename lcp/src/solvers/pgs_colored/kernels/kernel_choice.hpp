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

/// k, or the automatic choice for Auto on small problems (pgs_colored_auto_kernel(0)); throws
/// InvalidArgument when k is not available on this CPU (pgs_colored_kernel_available).
PgsColoredKernel resolve(PgsColoredKernel k);

/// The single-contact batches from which the compact layout applies with the AVX-512 kernel
/// (PgsColoredDef::compact_from_batches = −1) and from which Auto takes that kernel on Zen 5.
constexpr int kLargeFrom = 512;

/// What the automatic choice reads of the CPU: its AVX-512 and AVX2 kernels run on it, its
/// vendor is AMD, its family (cpu_family).
struct CpuTraits {
  bool avx512 = false, avx2 = false, amd = false;
  int family = 0;
};
CpuTraits this_cpu();

/// The kernel Auto sweeps a problem of `single_batches` single-contact batches with on `cpu`
/// (never Auto): AVX-512 when it runs, except on AMD CPUs with AVX2 before Zen 5 (family 0x1A)
/// and on Zen 5 below kLargeFrom batches, which take AVX2; else AVX2 when it runs, else scalar.
PgsColoredKernel auto_kernel_for(const CpuTraits& cpu, long single_batches);

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
