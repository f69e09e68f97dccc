#pragma once
// integrate_bodies on the step's threads (its contact impulse and body updates by jobs of
// bodies: impulse_parts.hpp, the same bits on every thread count), and integrate_bodies that
// also keeps the kinematic state from before the step, for World's lazy public problem with an
// internal body order (world.hpp: assembled on first read, on the bodies as they were at
// assemble()). The arrays are swapped, not copied: the previous x, v, ω move into the
// `previous_*` vectors and the step writes the new ones into the body state, so keeping them
// costs no extra pass over the bodies.
#include <Eigen/Core>
#include <vector>

#include "dc/core/vec2.hpp"
#include "dc/engine/body_state.hpp"
#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// integrate_bodies(problem, λ, g, Δt, bodies, impulse), bit for bit, on up to `threads` threads
/// (a scene with a shape table: on the calling thread).
void integrate_bodies_on(const LcpProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& lambda, Vec2 gravity, double dt,
                         BodyState& bodies, Eigen::VectorXd& impulse, int threads);

/// integrate_bodies(problem, λ, g, Δt, bodies, impulse), bit for bit, on up to `threads`
/// threads, leaving x, v, ω of before the step in previous_position, previous_velocity,
/// previous_omega (resized to the body count; their old contents are reused storage). Circle-only states are integrated from
/// the swapped arrays; with a shape table the state is copied first and integrated in place.
void integrate_bodies_keeping(const LcpProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& lambda, Vec2 gravity, double dt,
                              BodyState& bodies, Eigen::VectorXd& impulse,
                              std::vector<Vec2>& previous_position, std::vector<Vec2>& previous_velocity,
                              std::vector<double>& previous_omega, int threads = 1);

}  // namespace dc
