#include "collision/narrow_phase.hpp"

#include <cmath>

#include "det_math.hpp"

namespace dc {

std::optional<Contact> circle_circle(const BodyState& s, int a, int b, double threshold) {
  const auto ia = static_cast<size_t>(a), ib = static_cast<size_t>(b);
  Contact c;
  if (!circle_pair(s.position[ia], s.radius[ia], s.position[ib], s.radius[ib], a, b, threshold, c)) return std::nullopt;
  return c;
}

std::optional<Contact> circle_circle(const CircleProbe& pa, const CircleProbe& pb, int a, int b) {
  Contact c;
  if (!circle_pair(pa.centre, pa.radius, pb.centre, pb.radius, a, b, pa.spec + pb.spec, c)) return std::nullopt;
  return c;
}

std::optional<Contact> circle_wall(const BodyState& s, int k, Wall w, double width, double height,
                                   double threshold) {
  const auto i = static_cast<size_t>(k);
  Vec2 n;
  double dist = 0;  // centre distance to the wall plane, positive inside the box
  wall_plane(s.position[i], w, width, height, n, dist);
  const double gap = dist - s.radius[i];
  if (gap >= threshold) return std::nullopt;
  Contact c;
  fill_circle_wall(s.position[i], s.radius[i], k, w, n, gap, c);
  return c;
}

namespace {

/// Gap of a contact with a non-circle: n·(p_b − p_a) from the witness anchors, p = x + R(θ) anchor.
double anchored_gap(const BodyState& s, const Contact& c) {
  auto world_point = [&](int body, Vec2 anchor) {
    const auto k = static_cast<size_t>(body);
    double cs = 1, sn = 0;
    det_sincos(s.angle[k], sn, cs);  // as the shape narrow phase's poses (libm-free)
    return s.position[k] + Vec2{cs * anchor.x - sn * anchor.y, sn * anchor.x + cs * anchor.y};
  };
  const Vec2 pb = world_point(c.body_b, c.anchor_b);
  const Vec2 pa = c.body_a >= 0 ? world_point(c.body_a, c.anchor_a) : c.anchor_a;
  return dot(c.normal, pb - pa);
}

}  // namespace

double contact_gap(const BodyState& s, const Contact& c, double width, double height) {
  const auto ib = static_cast<size_t>(c.body_b);
  if (!s.shapes.empty() && (s.shapes.kind[ib] != ShapeKind::Circle ||
                            (c.body_a >= 0 && s.shapes.kind[static_cast<size_t>(c.body_a)] != ShapeKind::Circle)))
    return anchored_gap(s, c);
  if (c.body_a >= 0) {
    // As circle_circle: |x_b − x_a| − (r_a + r_b).
    const auto ia = static_cast<size_t>(c.body_a);
    const double rsum = s.radius[ia] + s.radius[ib];
    return std::sqrt(length_squared(s.position[ib] - s.position[ia])) - rsum;
  }
  Vec2 n;
  double dist = 0;
  wall_plane(s.position[ib], static_cast<Wall>(c.body_a), width, height, n, dist);
  return dist - s.radius[ib];
}

}  // namespace dc
