// pgs-colored's choice of kernels (kernel_choice.hpp) and the public kernel queries of
// dc/lcp/pgs_colored.hpp.
#include "solvers/pgs_colored/kernels/kernel_choice.hpp"

#include <string>

#include "dc/core/error.hpp"

namespace dc {
namespace colored {

PgsColoredKernel resolve(PgsColoredKernel k) {
  if (k != PgsColoredKernel::Auto) {
    if (!pgs_colored_kernel_available(k))
      throw InvalidArgument(std::string("pgs-colored: the ") + to_string(k) + " kernel is not available on this CPU");
    return k;
  }
  return pgs_colored_auto_kernel(0);
}

CpuTraits this_cpu() { return {cpu_has_avx512(), cpu_has_avx2(), cpu_is_amd(), cpu_family()}; }

PgsColoredKernel auto_kernel_for(const CpuTraits& cpu, long single_batches) {
  // AMD cores execute 512-bit operations as two 256-bit halves (Zen 4) or gain little from the
  // width on problems that stay in cache (Zen 5): there the AVX2 kernel is at least as fast on
  // small problems (it also skips the all-padding half of a colour's last batch; micro_pgs,
  // docs/lcp.md "pgs-colored"). From kLargeFrom batches on, the AVX-512 kernel's compact layout
  // streams fewer bytes per sweep (19 of the full layout's 27 doubles per lane), and a sweep
  // whose data does not fit in the caches is bound by those bytes: on Zen 5 it is the faster
  // one there (docs/engine.md "One step per contact row").
  // Elsewhere the AVX-512 kernel is preferred at every size.
  constexpr int kZen5 = 0x1A;
  if (cpu.avx512) {
    const bool amd_small = cpu.avx2 && cpu.amd && (cpu.family < kZen5 || single_batches < kLargeFrom);
    if (!amd_small) return PgsColoredKernel::Avx512;
  }
  if (cpu.avx2) return PgsColoredKernel::Avx2;
  return PgsColoredKernel::Scalar;
}

Kernels kernel_fn(PgsColoredKernel k) {
  switch (k) {
    case PgsColoredKernel::Avx512:
      return {sweep_avx512, sweep_pairs_avx512, {residual_avx512, residual_pairs_avx512, residual_compact_avx512},
              sweep_compact_avx512};
    case PgsColoredKernel::Avx2:
      return {sweep_avx2, sweep_pairs_avx2, {residual_avx2, residual_pairs_avx2}, sweep_compact_avx2};
    default:
      return {sweep_scalar, sweep_pairs_scalar, {residual_scalar, residual_pairs_scalar}, sweep_compact_scalar};
  }
}

}  // namespace colored

bool pgs_colored_kernel_available(PgsColoredKernel kernel) {
  switch (kernel) {
    case PgsColoredKernel::Avx512: return colored::cpu_has_avx512();
    case PgsColoredKernel::Avx2: return colored::cpu_has_avx2();
    default: return true;
  }
}

PgsColoredKernel pgs_colored_auto_kernel(long single_batches) {
  return colored::auto_kernel_for(colored::this_cpu(), single_batches);
}

const char* to_string(PgsColoredKernel kernel) {
  switch (kernel) {
    case PgsColoredKernel::Auto: return "auto";
    case PgsColoredKernel::Avx512: return "avx512";
    case PgsColoredKernel::Avx2: return "avx2";
    case PgsColoredKernel::Scalar: return "scalar";
  }
  return "?";
}

}  // namespace dc
