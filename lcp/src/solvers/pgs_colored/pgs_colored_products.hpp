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
#include "dc/lcp/lcp_problem.hpp"

namespace dc::colored {

/// du[kStride·k + d] = M⁻¹_c (Jᵀλ)_c Δt for column c = 3k + d (0 beyond J's columns), the
/// padding entry of each body 0, then the zero body (kStride zeros): `du` holds
/// kStride·(bodies + 1) doubles, bodies·3 ≥ J's columns. Serial; bit-identical to
/// lcp_problem.cpp's velocity_change. `jt` is scratch (Jᵀλ; kept by the caller, no allocation
/// in steady state).
void velocity_change(const LcpProblem& p, const Eigen::VectorXd& lambda, int bodies, double* du, Eigen::VectorXd& jt);

/// du[c] = M⁻¹_c (Jᵀλ)_c Δt in column order (du resized to J's columns), bit-identical to
/// lcp_problem.cpp's velocity_change for every thread count. On one thread: J's rows in order
/// (transpose_rows, the sums of Eigen's product).
/// On more: each thread owns a block of bodies (columns) and sums its columns over the rows in
/// ascending order, from 0 — Eigen's order per column, so the same bits — reading only the rows
/// that act on its bodies: those of the contacts on them, whose row range the threads first
/// bound from their share of the contacts (min/max: order-free). Requires what a successful
/// packing checked: every row belongs to a contact of p.constraints and acts only on that
/// contact's bodies.
void scaled_transpose_product(const LcpProblem& p, const Eigen::VectorXd& lambda, int threads, Eigen::VectorXd& du);

/// natural_residual(p, λ) bit for bit, using `du` as scratch (Δu in column order, kept by the
/// caller): Δu by scaled_transpose_product on one thread, then the rows (by contact,
/// contact_errors, when the contacts own the rows) on `threads` threads. `all_finite` is
/// set to whether every λ_i is finite. Same requirement as scaled_transpose_product.
double natural_residual(const LcpProblem& p, const Eigen::VectorXd& lambda, int threads, Eigen::VectorXd& du,
                        bool& all_finite);

}  // namespace dc::colored
