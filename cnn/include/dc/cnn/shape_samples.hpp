#pragma once
// What the shape channels of a feature image see of one body (feature_image.hpp: coverage,
// orient_c, orient_s): area-weighted sample points covering the body's real extent
// and the nematic orientation of its second area moment.
//
// Area samples (body frame, centroid at the origin). A polygon is cut into the fan triangles
// (0, v_i, v_{i+1}) — the centroid is inside a convex polygon — and each triangle T into m²
// congruent sub-triangles by the barycentric lattice A + (i/m)(B − A) + (j/m)(C − A); every
// sub-triangle contributes one sample at its centroid with weight |T|/m²:
//
//   "up"   (i + j ≤ m − 1): A + (3i + 1)/(3m)·(B − A) + (3j + 1)/(3m)·(C − A)
//   "down" (i + j ≤ m − 2): A + (3i + 2)/(3m)·(B − A) + (3j + 2)/(3m)·(C − A)
//
// m = ⌈(longest side of T) / spacing⌉, clamped to 1..kMaxSubdivision, so neighbouring samples
// are closer than the caller's spacing (the feature image passes h/2: every sample's kernel
// overlaps its neighbours' and the splat of a body is a smooth plateau, not a set of bumps).
// The weights sum to the polygon's area exactly (up to rounding) and the samples' first moment
// is 0 (each sub-triangle's centroid is its own first moment). A circle of radius r and an
// ellipse with semi-axes (a, b) use the inscribed 16-gon (a cos φ_i, b sin φ_i), φ_i = 2πi/16,
// with the weights scaled so that they sum to the true area π a b (the 16-gon holds 97.4 % of
// it).
//
// Nematic orientation. With the second area moments about the centroid in the body frame
//   J_xx = ∫ x² dA, J_yy = ∫ y² dA, J_xy = ∫ x y dA                              [m⁴]
// (polygon, c_i = v_i × v_{i+1}:
//   J_xx = 1/12 Σ c_i (x_i² + x_i x_{i+1} + x_{i+1}²),
//   J_yy = 1/12 Σ c_i (y_i² + y_i y_{i+1} + y_{i+1}²),
//   J_xy = 1/24 Σ c_i (x_i y_{i+1} + 2 x_i y_i + 2 x_{i+1} y_{i+1} + x_{i+1} y_i);
//  ellipse: J_xx = A a²/4, J_yy = A b²/4, J_xy = 0; circle: J_xx = J_yy, J_xy = 0)
// the body-frame nematic vector is
//   q = (J_xx − J_yy, 2 J_xy) / (J_xx + J_yy) = α (cos 2φ, sin 2φ)                  [1]
// where φ is the angle of the major principal axis and α = (λ₁ − λ₂)/(λ₁ + λ₂) ∈ [0, 1] the
// anisotropy of J (a w × h box: (w² − h²)/(w² + h²); an a × b ellipse: (a² − b²)/(a² + b²)).
// J_world = R(θ) J Rᵀ(θ), so the world-frame vector is q rotated by 2θ: invariant under θ → θ + π
// (a box flipped end to end is the same box) and 0 for circles and regular polygons, whose J is
// isotropic (|q| < 1e-12 is snapped to 0 so rounding does not invent an orientation).
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
