#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the serial sweep's plan, the colour ranges
// of the layout (pgs_colored_layout.hpp) as kernel calls. A range whose contacts fit in few lanes
// (chains such as stacks and pyramids colour into many such ranges) is swept by the scalar kernel,
// which visits only the lanes in use, instead of a vector kernel's 4- or 8-lane group with its
// transposes; consecutive scalar ranges of one kind (their batches adjacent in the batch array)
// are one call. Every kernel performs per lane the same operations in the same order
// (pgs_colored_batch.hpp) and a colour's lanes touch disjoint bodies, so the plan changes neither
// λ, Δu, θ nor the non-finite flag: only which kernel computes them.
#include <vector>

#include "solvers/pgs_colored/pgs_colored_layout.hpp"

namespace dc::colored {

/// Batches [begin, end) of one kind (pairs: pair batches) for one kernel call, in sweep order.
struct SweepStep {
  int begin, end;
  bool pairs;
  bool scalar;  // the scalar kernel, whatever the solver's kernel
};

/// Lanes up to which a range is swept by the scalar kernel: the contacts (single batches) or
/// manifolds (pair batches) of one batch. Above it a vector kernel's lane group pays off.
constexpr int kScalarLanes = 2;

/// The plan of prep's ranges, in their order, into `out` (cleared; its storage reused).
/// scalar_lanes: ranges of one batch with at most this many lanes in use take the scalar kernel
/// (0: none; the overflow set, one lane per batch, counts its batches one by one).
void plan_sweep(const Prepared& prep, int scalar_lanes, std::vector<SweepStep>& out);

}  // namespace dc::colored
