#pragma once
// What the contact forces λ of a step do to the world (docs/design.md §2), implemented once:
// World::integrate applies it to the world, and the bench evaluates candidate λ with it
// (penetration and energy after the step) without touching the world.
//
// Semi-implicit Euler with the step's contact impulse Δt Jᵀ λ [N·s] and gravity g:
//   v⁺ = v + (Δt g + m⁻¹ (Δt Jᵀ λ)_v),   ω⁺ = ω + I⁻¹ (Δt Jᵀ λ)_ω,
//   x⁺ = x + Δt v⁺,                      θ⁺ = θ + Δt ω⁺.
#include <Eigen/Core>
#include <span>
#include <vector>

#include "dc/engine/body_state.hpp"
#include "dc/engine/contact.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {

/// Advances the kinematic fields of `bodies` by one step of length dt with the contact forces
/// λ of `problem` (its J; A is not needed). `impulse` receives Δt Jᵀ λ per dof (3 per body:
/// x, y, angular) [N·s]. Throws InvalidArgument when λ does not have problem.rows() entries or
/// J does not have 3 columns per body. Runs on the calling thread (a World's step runs the same
/// integration by jobs of bodies on its threads, with the same bits).
void integrate_bodies(const LcpProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& lambda, Vec2 gravity, double dt,
                      BodyState& bodies, Eigen::VectorXd& impulse);

/// Σ ½ m |v|² + ½ I ω² [J].
double kinetic_energy(const BodyState& bodies);
/// Σ −m g·x [J] (zero at the origin).
double potential_energy(const BodyState& bodies, Vec2 gravity);

/// The world after one step with a given λ.
struct StepOutcome {
  BodyState bodies;           ///< state after the step
  Eigen::VectorXd impulse;    ///< Δt Jᵀ λ per dof [N·s]
  std::vector<double> gap;    ///< gap of each of this step's contacts at the new positions [m]
  double kinetic_energy = 0;  ///< [J]
  double potential_energy = 0;  ///< [J]

  [[nodiscard]] double energy() const { return kinetic_energy + potential_energy; }
  /// max(0, −min gap) over this step's contacts after the step [m].
  [[nodiscard]] double max_penetration() const;
};

/// What integrating the step with λ would give (integrate_bodies on a copy of `bodies`, then
/// the energies and the gaps of `contacts` by the narrow phase's contact_gap), without
/// changing anything. `out` is reused (no allocation once its vectors have grown).
void predict_step(const BodyState& bodies, std::span<const Contact> contacts, const LcpProblem& problem,
                  const WorldDef& def, const Eigen::VectorXd& lambda, StepOutcome& out);

}  // namespace dc
