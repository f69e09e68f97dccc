#pragma once
// The checks of WorldDef::validate that look at what the values imply rather than at each
// value alone (docs/robustness.md "Bad values refused at the door").
#include "dc/engine/world_def.hpp"

namespace dc {

/// Largest [bodies] count a scene may ask for. The engine is exercised up to 40,000 bodies;
/// a million circles already take ~1 GB of trajectory per 100 steps and minutes per step of
/// PGS, and ten million would take minutes just to be placed before anything is written.
inline constexpr int kMaxGeneratedBodies = 1000000;

/// Bound on every body's mass [kg], rotational inertia [kg m²], their inverses, and its
/// energy scale m (|g| (|x| + |y|) + ½ v²) + ½ I ω² [J] (x, y: where it starts): 1e100. The solver multiplies such quantities
/// (A = J M⁻¹ Jᵀ, λ = A⁻¹ b, energies summed over bodies), and three factors of at most 1e100
/// stay well below the largest double (1.8e308), so nothing overflows to inf or NaN. Physical
/// scenes are 1e-6 … 1e12 in SI units.
inline constexpr double kMaxMagnitude = 1e100;

/// ConfigError naming the key when a generated, explicit or inflow body's mass, inertia,
/// inverse mass or inertia, or energy scale is outside [1/kMaxMagnitude, kMaxMagnitude].
/// Part of WorldDef::validate.
void validate_derived_quantities(const WorldDef& def);

/// ConfigError "[bodies] count: …" when the generated bodies cannot fit: more than
/// kMaxGeneratedBodies, or more circle area than the densest packing of circles (a fraction
/// π/√12 ≈ 0.907) of where they are placed (the [bodies] region within the box; with the Gaussian,
/// the box and the disk of radius 6 σ + r around the mean, outside which no body lands in
/// practice: P = e^-18 per attempt). Checked when the bodies are made (World), not by
/// WorldDef::validate: a data set's template scene states a count that each simulation
/// replaces.
void validate_generated_count(const WorldDef& def);

}  // namespace dc
