#pragma once
// The pgs-colored kernels this CPU runs (scalar always, AVX2 and AVX-512 where present; the
// portable build runs the same list: the AVX kernels are chosen at run time), one PgsColoredDef
// each, for the tests that compare the kernels with each other or with pgs.
#include <vector>

#include "dc/lcp/pgs_colored.hpp"

namespace dc::test {

inline std::vector<PgsColoredDef> pgs_colored_kernel_defs() {
  std::vector<PgsColoredDef> out;
  for (PgsColoredKernel k : {PgsColoredKernel::Scalar, PgsColoredKernel::Avx2, PgsColoredKernel::Avx512}) {
    if (!pgs_colored_kernel_available(k)) continue;
    PgsColoredDef d;
    d.kernel = k;
    out.push_back(d);
  }
  return out;
}

}  // namespace dc::test
