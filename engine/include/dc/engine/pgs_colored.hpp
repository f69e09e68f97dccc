#pragma once
// "pgs-colored": matrix-free projected Gauss–Seidel in colour order (docs/design.md §8.4). The contacts
// are coloured (contact_coloring.hpp: no two contacts of a colour share a dynamic body) and a
// sweep solves colour 0, then colour 1, …, then the overflow set; the contacts of one colour
// are independent, so 8 of them are solved at once in AVX-512 lanes (double precision,
// normal + tangent row per contact as in "pgs", body velocities gathered and scattered per
// lane) and the batches of one colour can run on several threads (OpenMP).
//
// Same iteration as "pgs" in another row order: same fixed points, different iterates and
// sweep counts. The lane arithmetic is that of the scalar path operation for operation
// (explicit FMAs, the same tree sums, the clamps as compare-and-select with the semantics of
// the scalar branches), so the SIMD path, the scalar path and every thread count give
// bit-identical iterates.
//
// Colours are reused from the solver's previous solve where contacts persist (the solver
// object keeps that state: solves are deterministic for a fixed sequence of problems; two
// solves of the same problem in a row use the same colouring). Problems the coloured kernels
// do not cover (no contact constraints, singular rows, rows with other bounds) are solved by
// "pgs" instead, and the result's message says so.
#include <memory>

#include "dc/engine/lcp_solver.hpp"

namespace dc {

struct PgsColoredDef {
  /// OpenMP threads for the batches of a colour (1 = serial; 0 = OpenMP's default).
  /// Problems with fewer than `min_batches_per_thread`·threads batches of 8 contacts run serially.
  int threads = 1;
  int min_batches_per_thread = 32;
  /// Use the AVX-512 kernel when the build has one (DC_NATIVE on an AVX-512 CPU); false forces
  /// the scalar kernel (the tests compare both in one binary).
  bool simd = true;
  /// Reuse last solve's colours where contacts persist (false: greedy colouring from scratch).
  bool reuse_colors = true;
};

std::unique_ptr<LcpSolver> make_pgs_colored(const PgsColoredDef& def = {});

/// True when this build has the AVX-512 kernel of pgs-colored.
bool pgs_colored_has_simd();

}  // namespace dc
