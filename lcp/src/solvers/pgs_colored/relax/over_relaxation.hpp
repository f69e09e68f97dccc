#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): projected successive over-relaxation on the
// packed problem. A packed row stores J_i/A_ii and b_i/A_ii, and a kernel sets
// λ_i ← proj(λ_i − r_i) with r_i = b_i/A_ii + (J_i/A_ii)·Δu; scaling both by ω makes the same
// kernel compute λ_i ← proj(λ_i − ω r_i), "psor"'s update, while M⁻¹J_iᵀΔt (the Δu update by
// λ_i's change) is left as it is. So the three kernels need no change and stay bit-identical to
// each other for any ω. Scaled: every row solved one at a time (a single contact's normal and
// tangent rows, a two-point manifold's tangent rows); a manifold's 2 × 2 normal block is solved
// exactly (its c01, c10, inv_det are not scaled), as is every row of the "pgs" fallback.
// ω = 1 leaves the batches untouched (the caller does not call).
#include <vector>

#include "dc/lcp/lcp_solver.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"

namespace dc::colored {

/// Multiplies the J/A_ii and b/A_ii entries of every lane of a batch (normal and tangent rows),
/// or of a pair batch's tangent rows, by ω (padding lanes hold zeros and stay zero). The packing
/// scales each batch as it fills it, while the batch is in cache.
void over_relax(Batch& batch, double omega);
void over_relax(PairBatch& pair, double omega);

/// The InvalidInput result for o.omega outside (0, 2), where the iteration need not converge
/// (as "psor"'s): λ = λ⁰ when it fits p and is finite, else zero.
SolveResult invalid_omega(const LcpProblem& p, const Eigen::VectorXd& lambda0, const SolverOptions& o);

}  // namespace dc::colored
