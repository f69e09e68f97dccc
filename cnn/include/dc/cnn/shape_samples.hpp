#pragma once
// What the shape channels of a feature image see of one body (feature_image.hpp: coverage,
// orient_c, orient_s): area-weighted sample points covering the body's real extent and the
// nematic orientation of its second area moment (docs/learning.md "Shape channels").
// Samples (body frame): centroids of an m × m barycentric subdivision of the polygon's fan
// triangles, m = ⌈longest side / spacing⌉ so neighbours are closer than the caller's spacing
// (the feature image passes h/2, so a body splats as a smooth plateau); circles and ellipses use
// the inscribed 16-gon. Weights sum to the true area, first moment 0. Orientation: body-frame
// q = (J_xx − J_yy, 2 J_xy)/(J_xx + J_yy) = α (cos 2φ, sin 2φ) [1], J the second area moment
// [m⁴]; the world vector is q rotated by 2θ — invariant under θ → θ + π, 0 for circles and
// regular polygons (|q| < 1e-12 snaps to 0 so rounding does not invent an orientation).
#include <cstddef>
#include <vector>

#include "dc/core/vec2.hpp"
#include "dc/engine/body_state.hpp"

namespace dc {

/// One area sample: a point of the body and the area it stands for.
struct AreaSample {
  Vec2 point;        ///< body frame (centroid at the origin) [m]
  double area = 0;   ///< [m²]
};

/// Largest subdivision m of one fan triangle (m² samples): bounds the cost of long static plates.
inline constexpr int kMaxSubdivision = 32;

/// Appends the body-frame area samples of body k of `bodies` (see the file comment) with
/// sub-triangle sides below `spacing` [m] (> 0, else InvalidArgument). Bodies of a scene
/// without a shape table are circles of radius bodies.radius[k].
void append_area_samples(const BodyState& bodies, std::size_t k, double spacing, std::vector<AreaSample>& out);

/// The body-frame nematic vector q = (J_xx − J_yy, 2 J_xy)/(J_xx + J_yy) of body k [1]
/// (see the file comment); (0, 0) for circles and isotropic shapes.
Vec2 body_frame_nematic(const BodyState& bodies, std::size_t k);

/// q rotated by 2θ given (cos θ, sin θ): the nematic vector in the world frame.
inline Vec2 rotate_nematic(Vec2 q, double c, double s) {
  const double c2 = c * c - s * s, s2 = 2 * c * s;  // cos 2θ, sin 2θ without another libm call
  return {c2 * q.x - s2 * q.y, s2 * q.x + c2 * q.y};
}

}  // namespace dc
