#pragma once
// Assembly of the step's contact LCP (docs/design.md §2, docs/engine.md "Rows"):
//   J (sparse, rows × 3n):  normal row   [ −nᵀ, −(r_a × n),  nᵀ, (r_b × n) ]
//                           tangent row  [ −tᵀ, −(r_a × t),  tᵀ, (r_b × t) ]   (only if μ > 0)
//   M⁻¹ = diag(1/m_1, 1/m_1, 1/I_1, …);  A = J M⁻¹ Jᵀ Δt [m/(N·s)], λ a force [N], not formed here
//   b = J (u + Δt M⁻¹ F_ext) + stabilisation   [m/s]
// LcpProblem::constraints first (contact c owns its normal row and, when μ > 0, the tangent row
// right after it; contact_constraints.hpp), then J and b row by row. Stabilisation of normal rows
// (ContactSection):  gap g > 0 (speculative): b_n += g / Δt;
//   gap g ≤ 0 (Baumgarte): b_n += β · min(0, g + slop) / Δt;
//   restitution e > 0, bounce due, stored approach v_a < −threshold:
//     b_n = min(b_n, J_n u + J_n Δt M⁻¹ F_ext + e · v_a)   (restitution.hpp)
#include <vector>

#include "dc/engine/body_state.hpp"
#include "dc/engine/contact.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {

/// Friction coefficient μ of a contact: the scene's contact.friction for every contact today
/// (the one place a per-material μ will come from). μ = 0 gives the contact no tangent row.
inline double friction_of(const Contact& /*contact*/, const ContactSection& section) { return section.friction; }

/// Fills `out` (constraints, b, bounds, J, inv_mass, dt; A left empty) for the given
/// contacts; reuses its storage. threads > 1: the rows are filled by parallel jobs of contacts
/// (each contact's rows written by one job: the same numbers). Stamps out.structure once the
/// structure is complete (valid by construction: StructureStamp); cleared while it is written.
void assemble_lcp(const BodyState& bodies, const std::vector<Contact>& contacts,
                  const WorldDef& def, LcpProblem& out, int threads = 1);

}  // namespace dc
