#pragma once
// Private to "pgs-colored" (dc/engine/pgs_colored.hpp): the products with J around the sweeps —
// Δu⁰ = M⁻¹ Jᵀ λ⁰ Δt before them, the natural residual after them — bit for bit equal to the
// serial forms in lcp_problem.cpp (velocity_change, natural_residual), so a solve's result does
// not depend on the threads.
//
// Why the same bits. (Jᵀλ)_c is a sum over the rows acting on column c; Eigen's product of a
// row-major J's transpose with λ scatters row after row, adding J_ic·λ_i to 0 in ascending row
// order; velocity_change below is that product (then Δu_c = M⁻¹_c·s_c·Δt). It stays serial on
// purpose: a per-body index that lets threads own bodies cost more to build and to walk (random
// access into J) than this one sequential pass (≈ 0.4 ms CPU against ≈ 0.15 ms on a
// 10,000-body pile), so the solver overlaps it with other work instead (Δu⁰ with the packing).
// A row of w = J Δu + b is one dot product (storage order, from 0, then + b_i), and the residual
// max_i |λ_i − mid(lo_i, λ_i − w_i, hi_i)| is a max-reduction (order-free; any NaN → ∞, as the
// serial form): those rows run on threads.
#include "dc/engine/lcp_problem.hpp"

namespace dc::colored {

/// du[kStride·k + d] = M⁻¹_c (Jᵀλ)_c Δt for column c = 3k + d (0 beyond J's columns), the
/// padding entry of each body 0, then the zero body (kStride zeros): `du` holds
/// kStride·(bodies + 1) doubles, bodies·3 ≥ J's columns. Serial; bit-identical to
/// lcp_problem.cpp's velocity_change. `jt` is scratch (Jᵀλ; kept by the caller, no allocation
/// in steady state).
void velocity_change(const LcpProblem& p, const Eigen::VectorXd& lambda, int bodies, double* du, Eigen::VectorXd& jt);

/// natural_residual(p, λ) bit for bit, using `du` as scratch (Δu in column order, kept by the
/// caller): Δu on one thread, then the rows on `threads` threads. `all_finite` is set to whether
/// every λ_i is finite.
double natural_residual(const LcpProblem& p, const Eigen::VectorXd& lambda, int threads, Eigen::VectorXd& du,
                        bool& all_finite);

}  // namespace dc::colored
