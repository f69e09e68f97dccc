#pragma once
// Private to "pgs-colored" (dc/engine/pgs_colored.hpp): the products with J around the sweeps —
// Δu⁰ = M⁻¹ Jᵀ λ⁰ Δt before them, the natural residual after them — on the solver's OpenMP
// threads, bit for bit equal to the serial forms in lcp_problem.cpp (velocity_change,
// natural_residual) for every thread count, so a solve's result does not depend on the threads.
//
// Why the same bits. (Jᵀλ)_c is a sum over the rows acting on column c; Eigen's serial product
// adds J_ic·λ_i to 0 in ascending row order. BodyRows lists, per body, the rows acting on it in
// ascending order (the rows of the contacts touching it: pgs-colored has checked that every row
// acts on its own contact's bodies only), so a thread that owns a body adds the same products in
// the same order; Δu_c = M⁻¹_c·s_c·Δt as there. A row of w = J Δu + b is one dot product (storage
// order, from 0, then + b_i), and the residual max_i |λ_i − mid(lo_i, λ_i − w_i, hi_i)| is a
// max-reduction (order-free; any NaN → ∞, as the serial form). The index is built by a stable
// counting sort over row chunks, whose output does not depend on the number of chunks.
#include <vector>

#include "dc/engine/lcp_problem.hpp"

namespace dc::colored {

/// Per body k, the rows of J acting on it, ascending: rows[start[k] .. start[k+1]); per row, where
/// its second body's entries begin in J's storage (J's rows store their columns ascending, so the
/// lower body's entries come first). Reused between solves (the vectors keep their capacity).
struct BodyRows {
  std::vector<int> start;     ///< bodies + 1 offsets into rows
  std::vector<int> rows;      ///< row indices, ascending per body
  std::vector<int> row_body;  ///< per row: its contact's lower body and other body (−1: none)
  std::vector<int> split;     ///< per row: storage index of its other body's first entry (or the row's end)
  std::vector<int> cursor;    ///< threads × bodies: counts, then fill cursors
  bool ok = false;            ///< every row's entries are its lower body's, then its other body's
};

/// Builds `out` from p's contact constraints for `bodies` bodies (≥ 1 + every contact's body) on
/// `threads` threads. Requires every row to belong to exactly one contact (LcpProblem::validate)
/// and to act on its contact's bodies only (checked by pgs-colored's packing). out.ok = false
/// when a row stores its columns in another order: then velocity_change and natural_residual
/// must not be called (the serial forms are used).
void build_body_rows(const LcpProblem& p, int bodies, int threads, BodyRows& out);

/// du[kStride·k + d] = M⁻¹_c (Jᵀλ)_c Δt for column c = 3k + d (0 beyond J's columns), the
/// padding entry of each body 0, then the zero body (kStride zeros): `du` holds
/// kStride·(bodies + 1) doubles. Bit-identical to lcp_problem.cpp's velocity_change.
void velocity_change(const LcpProblem& p, const BodyRows& br, const Eigen::VectorXd& lambda, int threads,
                     double* du);

/// natural_residual(p, λ) bit for bit, using `du` (kStride·(bodies + 1) doubles) as scratch.
/// `all_finite` is set to whether every λ_i is finite.
double natural_residual(const LcpProblem& p, const BodyRows& br, const Eigen::VectorXd& lambda, int threads,
                        double* du, bool& all_finite);

}  // namespace dc::colored
