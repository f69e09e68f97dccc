#pragma once
// Narrow phase: analytic circle–circle and circle–wall contacts (docs/design.md §1: analytic
// tests for circles). A contact is created when the gap g is below the pair's
// speculative distance s_a + s_b, with s_k = margin/2 + |v_k| Δt (walls have s = 0, and
// the circle then gets the whole margin): a row whose gap is still open only stops the
// bodies from closing more than g within the step (b_n += g/Δt), so fast bodies cannot
// tunnel, while slow distant pairs create no rows at all.
#include <optional>

#include "dc/engine/body_state.hpp"
#include "dc/engine/contact.hpp"
#include "dc/engine/circle_probe.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {

/// Speculative reach s_k of body k [m].
double speculative_reach(const BodyState& s, int k, const ContactSection& c, double dt);

/// Contact between circles a and b when their gap is below `threshold` [m].
/// Coincident centres (distance < 1e-12·(r_a + r_b)) use the normal (0, 1), so that the
/// outcome is deterministic and finite; the overlap is then r_a + r_b.
std::optional<Contact> circle_circle(const BodyState& s, int a, int b, double threshold);
/// circle_circle(s, a, b, s_a + s_b) from the packed records `pa`, `pb` of bodies a and b: the
/// same contact, bit for bit.
std::optional<Contact> circle_circle(const CircleProbe& pa, const CircleProbe& pb, int a, int b);

/// Contact between circle k and wall `w` of a box of the given size, when the gap is
/// below `threshold` [m]. Normals point from the wall into the box.
std::optional<Contact> circle_wall(const BodyState& s, int k, Wall w, double width, double height,
                                   double threshold);

/// Signed gap [m] of contact c's pair (two circles, or a circle and the wall c.body_a of the
/// width × height box) at the positions of `s`, computed as circle_circle / circle_wall do.
/// Measures what a step did to this step's contacts (StepOutcome). A contact with a
/// non-circle (shape table present) is re-measured from its witness anchors instead.
double contact_gap(const BodyState& s, const Contact& c, double width, double height);

}  // namespace dc
