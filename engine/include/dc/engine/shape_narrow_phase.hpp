#pragma once
// The collide() stage of a scene with shapes or static/kinematic bodies (World runs it instead
// of its circle-only loop whenever BodyState::shapes is not empty):
//
//   * per body: world-frame polygon vertices/normals (cos θ, sin θ once per step), the
//     speculative reach s_k = margin/2 + |v_k| Δt + |ω_k| Δt R_k (R_k the bounding radius, so
//     rotating corners are covered; circles keep the circle formula), and its real
//     axis-aligned box grown by s_k;
//   * walls against dynamic bodies (circle_wall for circles, collide_shape_plane otherwise);
//   * broad phase on the boxes; pairs of two non-dynamic bodies are skipped; a pair with one
//     static or kinematic body is oriented so that body_a is that body (normal into the dynamic
//     one, like a wall); circle pairs use circle_circle, the others collide_shapes;
//   * contacts sorted by key.
#include <vector>

#include "dc/engine/body_state.hpp"
#include "dc/engine/broad_phase.hpp"
#include "dc/engine/contact.hpp"
#include "dc/engine/shape_collide.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {

/// Speculative reach of body k in a scene with shapes [m] (see above).
double shape_speculative_reach(const BodyState& s, int k, const ContactSection& c, double dt);

class ShapeNarrowPhase {
 public:
  /// Fills `contacts` (cleared first) for the bodies of `s`.
  void collide(const BodyState& s, const WorldDef& def, UniformGridBroadPhase& broad_phase,
               std::vector<Contact>& contacts);
  /// The pose of body k after the last collide() (polygons point into this object's buffers).
  [[nodiscard]] ShapePose pose(const BodyState& s, int k) const;
  /// libccd method for the pairs that need it (GJK+EPA by default).
  CcdMethod method = CcdMethod::GjkEpa;

 private:
  void update_poses(const BodyState& s);
  std::vector<double> cos_, sin_;
  std::vector<Vec2> world_vertices_, world_normals_;
  std::vector<Vec2> lo_, hi_;
  std::vector<double> spec_;
  std::vector<std::pair<int, int>> pairs_;
};

/// Pose of body k of `s` with its polygon transformed into caller-provided buffers (at least
/// shapes.vertex_count(k) entries each); for tests and scene construction.
ShapePose make_pose(const BodyState& s, int k, std::vector<Vec2>& world_vertices, std::vector<Vec2>& world_normals);

}  // namespace dc
