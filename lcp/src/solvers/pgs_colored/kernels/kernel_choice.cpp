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
  return pgs_colored_auto_kernel();
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

PgsColoredKernel pgs_colored_auto_kernel() {
  // AMD cores (Zen 4) execute 512-bit operations as two 256-bit halves: there the AVX2 kernel
  // is at least as fast (it also skips the all-padding half of a colour's last batch; micro_pgs,
  // docs/lcp.md "pgs-colored"). Elsewhere the AVX-512 kernel is preferred.
  if (colored::cpu_has_avx512() && !(colored::cpu_has_avx2() && colored::cpu_is_amd())) return PgsColoredKernel::Avx512;
  if (colored::cpu_has_avx2()) return PgsColoredKernel::Avx2;
  return PgsColoredKernel::Scalar;
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
