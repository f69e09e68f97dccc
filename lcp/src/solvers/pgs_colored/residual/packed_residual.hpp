#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the closing natural residual on the packed
// layout, from the Δu the sweeps maintain (a sweep's row products without the update), instead of
// forming M⁻¹JᵀλΔt again from J's CSR arrays and gathering J·Δu row by row.
//
// Per packed row i (slot s of the permuted λ): r̃_i = the sweep kernels' scaled residual
// (b + fma(j0,a0,j1·a1)) + (fma(j2,a2,j3·v0) + fma(j4,v1,j5·v2)) with j = ω_i J_i/A_ii and
// b = ω_i b_i/A_ii (ω_i = ω for the relaxed rows, 1 for a pair's normal rows), then
// w_i = (r̃_i·A_ii)/ω_i and error_i = |λ_i − clamp(λ_i − w_i, l_i, h_i)| with the bounds
// [0, ∞) of a normal row and ±μ·max(0, λ_n) of a tangent row (lcp_problem.cpp's natural
// residual). The residual is the maximum of the errors (order-free: the same bits for every
// split over threads); a NaN error is flagged instead. Padding lanes (zero rows, λ = 0, A = 1)
// have error 0.
//
// w_i equals lcp_problem.cpp's J_iΔu + b_i up to rounding: the maintained Δu is Δu⁰ plus the
// sweeps' updates, the same M⁻¹JᵀλΔt in exact arithmetic, and the rows are the scaled ones. It is
// valid only when Δu belongs to the returned λ (no sweep stopped on a non-finite value, Δu⁰
// finite) and every J entry is finite (a static body's slot then contributes exactly 0).
//
// The three kernels (scalar, AVX2, AVX-512) perform per lane the same operations in the same
// order, so they give the same bits.
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_layout.hpp"

namespace dc::colored {

struct ResidualAcc {
  double r = 0.0;    // the largest error that is not NaN
  bool nan = false;  // some error is NaN
};

/// The errors of batches [b0, b1): λ at lam + 16·bi, A_ii at diag + 16·bi (the permuted slots).
using ResidualKernel = void (*)(const Batch* batches, int b0, int b1, const double* lam, const double* diag,
                                const double* u, double omega, ResidualAcc& acc);
/// The errors of pair batches [b0, b1): λ at lam + 32·bi, A_ii at diag + 32·bi (lam and diag
/// start at the pairs' first slot, Prepared::pair_base).
using PairResidualKernel = void (*)(const PairBatch* pairs, int b0, int b1, const double* lam, const double* diag,
                                    const double* u, double omega, ResidualAcc& acc);

void residual_scalar(const Batch* batches, int b0, int b1, const double* lam, const double* diag, const double* u,
                     double omega, ResidualAcc& acc);
void residual_pairs_scalar(const PairBatch* pairs, int b0, int b1, const double* lam, const double* diag,
                           const double* u, double omega, ResidualAcc& acc);
/// Call only when cpu_has_avx2() / cpu_has_avx512() is true.
void residual_avx2(const Batch* batches, int b0, int b1, const double* lam, const double* diag, const double* u,
                   double omega, ResidualAcc& acc);
void residual_pairs_avx2(const PairBatch* pairs, int b0, int b1, const double* lam, const double* diag,
                         const double* u, double omega, ResidualAcc& acc);
void residual_avx512(const Batch* batches, int b0, int b1, const double* lam, const double* diag, const double* u,
                     double omega, ResidualAcc& acc);
void residual_pairs_avx512(const PairBatch* pairs, int b0, int b1, const double* lam, const double* diag,
                           const double* u, double omega, ResidualAcc& acc);

/// The kernels of one ISA.
/// The errors of compact batches [b0, b1) (compact/compact_batch.hpp), as ResidualKernel's.
using CompactResidualKernel = void (*)(const CompactBatch* batches, int b0, int b1, const double* lam,
                                       const double* diag, const double* u, double omega, ResidualAcc& acc);
void residual_compact_avx512(const CompactBatch* batches, int b0, int b1, const double* lam, const double* diag,
                             const double* u, double omega, ResidualAcc& acc);

struct ResidualKernels {
  ResidualKernel single;
  PairResidualKernel pairs;
  /// nullptr: compact batches are expanded for `single` (expand_rows).
  CompactResidualKernel compact = nullptr;
};

/// The errors of every batch and pair batch of `prep` with λ permuted (lam, Prepared::row_of's
/// slots), A_ii from prep.diag and Δu from prep.du, on `threads` threads of the calling thread's
/// team (chunks of batches; max and or combine them in any order alike). Each chunk then writes
/// its λ in row order, lambda_out[row_of[s]] = lam[s] (every row has one slot), while it is in
/// cache.
ResidualAcc packed_residual(const Prepared& prep, const double* lam, double omega, const ResidualKernels& k,
                            int threads, double* lambda_out);

}  // namespace dc::colored
