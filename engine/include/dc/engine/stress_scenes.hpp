#pragma once
// The extreme scenes of `deepcontact stress` and of the engine's extreme-scene tests
// (docs/robustness.md): each builder returns a complete, valid WorldDef (explicit [[body]]
// circles unless stated), with [time] steps set to a sensible default; callers may change any
// field. The instrumented run loop and the verdicts are the bench's (dc/bench/stress_scenarios.hpp).
#include <cstdint>

#include "dc/core/vec2.hpp"
#include "dc/engine/body_state.hpp"
#include "dc/engine/shape.hpp"
#include "dc/engine/world_def.hpp"

namespace dc::stress {

/// A circle body at (x, y) [m] with radius r [m] and areal density rho [kg/m²].
BodyDef circle(double x, double y, double r = 1.0, double rho = 1.0);

/// A definition with no generated circles and a box of width × height [m].
WorldDef explicit_scene(double width, double height);

/// Two light circles on the floor, wedged between the walls of a 4 m wide box, and a third
/// circle resting on both (the pyramid of three). ratio = ρ_heavy / ρ_light = m ratio.
/// heavy_on_top: the top circle is heavy; otherwise the two bottom circles are.
WorldDef pyramid_mass_ratio(double ratio, bool heavy_on_top);

/// A vertical stack of two circles on the floor (exactly touching), top/bottom mass ratio.
WorldDef stack_mass_ratio(double top_over_bottom);

/// `count` generated circles (r = 1) falling into a 12 m wide box: the Δt sweeps.
WorldDef small_pile(int count, double dt, std::uint64_t seed = 3);

/// A column of n circles (r = 1, explicit bodies) with 1 mm gaps, centred in a 10 m wide box
/// tall enough to hold it, friction μ.
WorldDef column(int n, double mu = 0.5);

/// `count` generated circles of radius 1, uniformly spread at areal coverage 0.25 for every
/// count (box side grows with √count): the broad-phase scaling scene.
WorldDef many_bodies(int count);

/// The seed scene scaled to `count` circles at the seed's density: box side 3√count m, the
/// Gaussian's mean at the centre, σ = 0.465√count m (30 m and 4.65 m for the seed's 100); the
/// other settings are the defaults. The pile of micro_step, step_threads and the body-order tests.
WorldDef scaled_seed_pile(int count);

/// The small pyramid-and-pile scene scaled by s: box, radii, positions, slop, margin,
/// restitution threshold and gravity × s, Δt unchanged. With time unchanged every length,
/// velocity and acceleration scales by s, masses by s² (ρ fixed), forces by s³, and the
/// contact LCP is the same problem in scaled units, so positions / s must agree.
WorldDef scaled_scene(double s);

/// The seed scene with `count` circles and friction μ.
WorldDef friction_scene(double mu, int count = 30);

/// Circles exactly touching: a row of four on the floor (centre distance 2r exactly, each
/// on the floor with gap 0) and one exactly on top of the second.
WorldDef exactly_touching();

/// Circles in all four corners, each touching both walls, plus one thrown into the lower
/// left corner diagonally at 20 m/s.
WorldDef corners();

/// A world definition for the coincident-centre state (coincident_state): two walls-free
/// sections can be chosen; explicit bodies are not used (World(def, state)).
WorldDef coincident_def(bool walls_and_gravity);
/// `copies` circles of radius 1 sharing the centre (15, 15) (not constructible from a scene
/// file, whose explicit bodies must not overlap).
BodyState coincident_state(int copies, double density_ratio = 1.0);

/// No walls, no gravity: `count` generated circles plus one heavy fast projectile (density
/// ratio `ratio`) fired into them: linear momentum must be conserved.
WorldDef free_collision(int count, double ratio, double mu);

/// n boxes of `size` stacked on the floor, exactly touching, centred in the box.
WorldDef box_stack(int n, Vec2 size);
/// A pyramid of unit boxes, `base` in the bottom row, each row offset by half a box.
WorldDef box_pyramid(int base);
/// `count` generated bodies of one shape (Box: size = dims; Ellipse: semi_axes = dims)
/// falling into a 20 × 20 box.
WorldDef shape_extremes(BodyShape shape, Vec2 dims, int count);

}  // namespace dc::stress
