#pragma once
// "pgs-colored": matrix-free projected Gauss–Seidel in colour order (docs/design.md §8.4). The contacts
// are coloured (contact_coloring.hpp: no two contacts of a colour share a dynamic body) and a
// sweep solves colour 0, then colour 1, …, then the overflow set; the contacts of one colour
// are independent, so 8 of them are solved at once in SIMD lanes (double precision, normal +
// tangent row per contact as in "pgs", body velocities gathered and scattered per lane) and the
// batches of one colour can run on several threads (OpenMP). Three kernels: AVX-512 (one zmm
// register per 8 lanes), AVX2 (two ymm registers) and scalar; the AVX ones are compiled in every
// x86-64 build and chosen at run time from the CPU (PgsColoredKernel::Auto).
//
// Same iteration as "pgs" in another row order: same fixed points, different iterates and
// sweep counts. The lane arithmetic is that of the scalar kernel operation for operation
// (explicit FMAs, the same tree sums, the clamps as compare-and-select with the semantics of
// the scalar branches), so the three kernels and every thread count give bit-identical
// iterates.
//
// Colours are reused from the solver's previous solve where contacts persist (the solver
// object keeps that state: solves are deterministic for a fixed sequence of problems; two
// solves of the same problem in a row use the same colouring). Problems the coloured kernels
// do not cover (no contact constraints, singular rows, rows with other bounds) are solved by
// "pgs" instead, and the result's message says so.
#include <memory>

#include "dc/engine/lcp_solver.hpp"

namespace dc {

// PgsColoredKernel, the sweep kernel, is declared in lcp_solver.hpp (SolverId names it).

struct PgsColoredDef {
  /// OpenMP threads for the set-up and the batches of a colour (1 = serial; 0 = OpenMP's
  /// default). Problems with fewer than `min_batches_per_thread`·threads batches of 8
  /// contacts run serially.
  int threads = 1;
  int min_batches_per_thread = 32;
  /// Which kernel sweeps (default Auto). make_pgs_colored throws InvalidArgument for a kernel
  /// this build or CPU cannot run (pgs_colored_kernel_available).
  PgsColoredKernel kernel = PgsColoredKernel::Auto;
  /// Reuse last solve's colours where contacts persist (false: greedy colouring from scratch).
  bool reuse_colors = true;
  /// Contacts per chunk of the parallel colouring (contact_coloring.hpp, "Threads"; 4,096 is
  /// the measured choice): a function of the contact count only, so the colours do not depend
  /// on `threads`. Problems with fewer than 2·color_chunk contacts are coloured as one chunk.
  /// 0 (the default) = the serial greedy colouring always: the chunked one needs one colour
  /// more on large piles (hex pile of 10,000: 5 instead of 4), which costs the 2-thread sweeps
  /// more than the parallel colouring saves (results.md "Threads: the colouring in parallel").
  int color_chunk = 0;
};

std::unique_ptr<LcpSolver> make_pgs_colored(const PgsColoredDef& def = {});

/// True when this build and CPU can run `kernel` (Auto and Scalar: always).
bool pgs_colored_kernel_available(PgsColoredKernel kernel);

/// The kernel Auto resolves to on this CPU (never Auto).
PgsColoredKernel pgs_colored_auto_kernel();

/// "auto", "avx512", "avx2" or "scalar".
const char* to_string(PgsColoredKernel kernel);

}  // namespace dc
