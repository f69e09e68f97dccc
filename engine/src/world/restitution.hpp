#pragma once
// Restitution with speculative contacts (docs/design.md §8.3).
//
// A speculative contact closes its gap in the step before impact: its row lets the bodies
// approach at −gap/Δt and they end that step touching, so the relative normal velocity read
// at the next step is that closing speed, not the impact speed. Each contact therefore
// remembers the approach velocity v_a = J_n u it had when its row first acted, carried by key
// (ContactKey) from step to step, and the normal row of the step after (or of the same step,
// for a contact that is already touching when its row first acts) aims at the separating
// velocity −e·v_a:
//
//   b_n = min(b_n, J_n u + J_n Δt M⁻¹ F_ext + e·v_a)     when e > 0 and v_a < −threshold
//
// (the more demanding of the stabilised target and the bounce). The bounce is applied once per
// impact; a resting contact has v_a ≈ 0 and stays quiet. With e = 0 nothing here runs.
#include <span>

#include "dc/engine/body_state.hpp"
#include "dc/engine/contact.hpp"

namespace dc {

/// Relative normal velocity J_n u of contact c [m/s] (negative: the bodies approach).
double relative_normal_velocity(const BodyState& bodies, const Contact& c);

/// Sets approach_velocity and restitution_due of every contact of `current` from its
/// predecessor in `previous` (same key; both sorted by key, as World keeps them):
///   * new, or its row did not act last step (λ_n = 0): v_a = J_n u now; due now if it already
///     touches (gap ≤ 0);
///   * its row acted last step for the first time (predecessor not due, v_a ≠ 0): v_a carried,
///     due now — the step after the speculative row closed the gap;
///   * otherwise (resting, or the bounce was applied): v_a = 0, not due.
void track_approach_velocities(const BodyState& bodies, std::span<const Contact> previous,
                               std::span<Contact> current);

}  // namespace dc
