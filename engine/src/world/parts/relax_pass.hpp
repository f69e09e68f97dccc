#pragma once
// The bias-free relax pass of a step (`[solver] relax_sweeps`, docs/engine.md "Relax pass"):
// the solve with Baumgarte's position bias gives λ_b, whose velocities move the bodies; a few
// more sweeps on the same rows without that bias, from λ_b, give λ_r, whose velocities the
// bodies keep. The velocity Baumgarte injects to separate an overlap, β·(g + slop)/Δt per
// contact, then moves the bodies apart once instead of staying in them (Box2D v3's "relax"
// iterations; Box2D 2.x's split impulses separate the two in the same way).
#include <span>

#include <Eigen/Core>

#include "dc/engine/body_state.hpp"
#include "dc/engine/contact.hpp"
#include "dc/engine/world_def.hpp"
#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// b ← b without the Baumgarte term of the normal row of every penetrating contact
/// (gap ≤ 0: b_n −= β·min(0, g + slop)/Δt, docs/engine.md "Rows"); contacts[c] is the
/// contact of constraint c. A row whose restitution bounce is due this step is left as it is
/// (its b is the bounce target, which the bias does not enter once the target is the lower).
void remove_position_bias(std::span<const Contact> contacts, const ContactConstraints& cons, const ContactSection& cs,
                          double dt, Eigen::Ref<Eigen::VectorXd> b);

/// x_k += Δt·m_k⁻¹·Δt·(Jᵀ(λ_b − λ_r))_k and θ_k += Δt·I_k⁻¹·… : the positions of bodies
/// integrated with λ_r moved to where λ_b's velocities take them (the bodies' velocities stay
/// λ_r's). Bodies with no inverse mass (static, kinematic) do not move. dl and impulse are
/// scratch storage.
void shift_positions(const LcpProblem& p, const Eigen::VectorXd& lambda_b, const Eigen::Ref<const Eigen::VectorXd>& lambda_r, double dt,
                     BodyState& s, Eigen::VectorXd& dl, Eigen::VectorXd& impulse);

}  // namespace dc
