#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the products with J around the sweeps —
// Δu⁰ = M⁻¹ Jᵀ λ⁰ Δt before them, the natural residual after them — bit for bit equal to the
// serial forms in lcp_problem.cpp (velocity_change, natural_residual), so a solve's result does
// not depend on the threads. (Jᵀλ)_c is Eigen's row-major scatter: J_ic·λ_i added to 0 in
// ascending row order. velocity_change is that product, serial on purpose: a per-body index for
// threads costs more to build and walk than one sequential pass, so the solver overlaps it with
// the packing. The residual's Jᵀλ is serial too (its split by blocks of bodies reads each row
// once per block it reaches and costs more than it saves); its rows run on threads: a row of
// w = J Δu + b is one dot product (storage order, from 0, then + b_i), and the max-reduction is
// order-free (any NaN → ∞, as serial).
// With skip_zero (allowed when every J entry is finite, values_finite) the Jᵀλ sums leave out
// the rows with λ_i = ±0, which add nothing to them (pgs_colored_residual.hpp).
#include "dc/lcp/lcp_problem.hpp"

namespace dc::colored {

/// du[kStride·k + d] = M⁻¹_c (Jᵀλ)_c Δt for column c = 3k + d (0 beyond J's columns), the
/// padding entry of each body 0, then the zero body (kStride zeros): `du` holds
/// kStride·(bodies + 1) doubles, bodies·3 ≥ J's columns. Serial; bit-identical to
/// lcp_problem.cpp's velocity_change. `jt` is scratch (Jᵀλ; kept by the caller, no allocation
/// in steady state). skip_zero (only when values_finite(p), pgs_colored_residual.hpp): rows with
/// λ_i = ±0 are not read, the same bits. Returns whether every entry of `du` is finite.
bool velocity_change(const LcpProblem& p, const Eigen::VectorXd& lambda, int bodies, double* du, Eigen::VectorXd& jt,
                     bool skip_zero = false);

/// velocity_change with values_finite(p)'s test folded into its pass over J: j_finite ←
/// values_finite(p), and the rows with λ_i = ±0 are skipped in each chunk of rows whose entries
/// are all finite (transpose_rows_checked). The bits of velocity_change(p, λ, bodies, du, jt,
/// values_finite(p)) with one pass over J's values instead of two. With `slot` (a permutation of
/// the bodies, the solver's Δu slots) body k's entries are at du[kStride·slot[k] + d]. With
/// check = false (the packing, which runs at the same time, verifies J finite: scale_rows, and
/// its failure discards Δu⁰) the test is left out and j_finite is set to true.
bool velocity_change_checked(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda, int bodies, double* du,
                             Eigen::VectorXd& jt, bool& j_finite, const int* slot = nullptr, bool check = true);

/// du[c] = M⁻¹_c (Jᵀλ)_c Δt in column order (du resized to J's columns), bit-identical to
/// lcp_problem.cpp's velocity_change for every thread count. On one thread: J's rows in order
/// (transpose_rows, the sums of Eigen's product).
/// On more: each thread owns a block of bodies (columns) and sums its columns over the rows in
/// ascending order, from 0 — Eigen's order per column, so the same bits — reading only the rows
/// that act on its bodies: those of the contacts on them, whose row range the threads first
/// bound from their share of the contacts (min/max: order-free). Requires what a successful
/// packing checked: every row belongs to a contact of p.constraints and acts only on that
/// contact's bodies. skip_zero as in velocity_change.
void scaled_transpose_product(const LcpProblem& p, const Eigen::VectorXd& lambda, int threads, Eigen::VectorXd& du,
                              bool skip_zero = false);

/// natural_residual(p, λ) bit for bit, using `du` as scratch (Δu in column order, kept by the
/// caller): Δu by scaled_transpose_product on one thread, then the rows (by contact,
/// contact_errors, when the contacts own the rows) on `threads` threads. `all_finite` is
/// set to whether every λ_i is finite. Same requirement as scaled_transpose_product; skip_zero
/// as in velocity_change (the rows with λ_i = 0 still have their errors), and the rows of a
/// contact whose bodies have Δu = 0 are not read either (contact_errors's skip_rest).
double natural_residual(const LcpProblem& p, const Eigen::VectorXd& lambda, int threads, Eigen::VectorXd& du,
                        bool& all_finite, bool skip_zero = false);

}  // namespace dc::colored
