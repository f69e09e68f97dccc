#pragma once
// Packed per-body record for the circle narrow phase. BodyState keeps one array per field; the
// narrow phase visits the two bodies of each candidate pair (body b is anywhere in memory unless
// the bodies follow space) and would read one cache line per field it needs. collide() writes
// the fields it reads into one 32-byte record per body in its streaming pass over the bodies
// (where it computes the speculative reach), aligned so that a record never straddles a cache
// line, and the pair test reads one line per body. The copies are exact: the same contacts.
#include <vector>

#include "dc/core/vec2.hpp"

namespace dc {

/// What the circle narrow phase reads of body k: centre x_k [m], radius r_k [m] and
/// speculative reach s_k [m] (narrow_phase.hpp).
struct alignas(32) CircleProbe {
  Vec2 centre;
  double radius = 0;
  double spec = 0;
};
static_assert(sizeof(CircleProbe) == 32);

}  // namespace dc
