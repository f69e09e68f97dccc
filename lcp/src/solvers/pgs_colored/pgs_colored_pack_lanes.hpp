#pragma once
// Private to "pgs-colored" (dc/lcp/pgs_colored.hpp): the packing of a batch of single contacts
// slot by slot across its 8 lanes (each coefficient of the 8 lanes in one pass: gathers and
// whole-row stores instead of one contact's scattered lane writes), for the usual storage of J
// (the engine's: each row holds the columns of its contact's bodies once each, in order). The
// same numbers as pgs_colored_layout.cpp's lane-by-lane pack_contact, bit for bit: per lane
// r_s = 0 + J_is, m_s = r_s·M⁻¹·Δt, A_ii = Σ_s r_s·m_s in slot order from 0.
#include <cstdint>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"

namespace dc::colored {

/// Packs contacts[0, lanes) into the lanes of B (rows unscaled, as pack_contact: j = J_i, mj =
/// M⁻¹J_iᵀΔt, b = b_i, μ, the bodies' Δu offsets and store flags) and pads lanes [lanes, W) (zero
/// rows, the zero body, row −1, A_ii = 1); writes the normal and tangent rows of each lane to
/// row_n / row_t and A_ii to diag_n / diag_t (1 for a contact without friction). Returns false,
/// having written part of B, when a row of one of the contacts is not stored in the usual way:
/// the caller then packs the batch lane by lane (which names a row acting on another body).
bool pack_lanes(const LcpProblem& p, const std::vector<std::uint8_t>& dynamic, int zero, const int* contacts,
                int lanes, Batch& B, int* row_n, int* row_t, double* diag_n, double* diag_t);

}  // namespace dc::colored
