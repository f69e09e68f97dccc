// pgs-colored's automatic kernel choice (kernels/kernel_choice.hpp): AVX-512 where it runs,
// except on AMD CPUs with AVX2 before Zen 5 (family 0x1A) at every size and on Zen 5 below
// kLargeFrom single batches, which take AVX2; AVX2 without AVX-512; scalar without either.
#include <gtest/gtest.h>

#include "solvers/pgs_colored/kernels/kernel_choice.hpp"

namespace dc::colored {
namespace {

TEST(PgsColoredKernelChoice, AutoFollowsTheCpuAndTheProblemSize) {
  const CpuTraits zen4{true, true, true, 0x19}, zen5{true, true, true, 0x1A}, intel{true, true, false, 6};
  const CpuTraits avx2_only{false, true, true, 0x1A}, neither{false, false, false, 6};
  for (const long batches : {0L, 1L, static_cast<long>(kLargeFrom), 100000L}) {
    EXPECT_EQ(auto_kernel_for(zen4, batches), PgsColoredKernel::Avx2) << batches;
    EXPECT_EQ(auto_kernel_for(intel, batches), PgsColoredKernel::Avx512) << batches;
    EXPECT_EQ(auto_kernel_for(avx2_only, batches), PgsColoredKernel::Avx2) << batches;
    EXPECT_EQ(auto_kernel_for(neither, batches), PgsColoredKernel::Scalar) << batches;
  }
  EXPECT_EQ(auto_kernel_for(zen5, kLargeFrom - 1), PgsColoredKernel::Avx2);
  EXPECT_EQ(auto_kernel_for(zen5, kLargeFrom), PgsColoredKernel::Avx512);
  EXPECT_EQ(auto_kernel_for(CpuTraits{true, true, true, 0x1B}, kLargeFrom), PgsColoredKernel::Avx512);
}

TEST(PgsColoredKernelChoice, ThisCpuIsWhatTheChoiceReads) {
  const CpuTraits cpu = this_cpu();
  EXPECT_EQ(cpu.avx512, pgs_colored_kernel_available(PgsColoredKernel::Avx512));
  EXPECT_EQ(cpu.avx2, pgs_colored_kernel_available(PgsColoredKernel::Avx2));
  for (const long batches : {0L, static_cast<long>(kLargeFrom)})
    EXPECT_EQ(pgs_colored_auto_kernel(batches), auto_kernel_for(cpu, batches)) << batches;
  EXPECT_EQ(resolve(PgsColoredKernel::Auto), pgs_colored_auto_kernel(0));
#if defined(__x86_64__) && defined(__GNUC__)
  EXPECT_GE(cpu.family, 6);  // every x86-64 CPU reports a family of 6 or more
#endif
}

}  // namespace
}  // namespace dc::colored
