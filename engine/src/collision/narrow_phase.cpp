#include "collision/narrow_phase.hpp"

#include <cmath>

#include "det_math.hpp"

namespace dc {
namespace {

/// Unit normal of wall w (from the wall into the box) and the distance of x to the wall's
/// plane, positive inside the box [m].
void wall_plane(Vec2 x, Wall w, double width, double height, Vec2& n, double& dist) {
  switch (w) {
    case Wall::Left: n = {1, 0}; dist = x.x; break;
    case Wall::Right: n = {-1, 0}; dist = width - x.x; break;
    case Wall::Bottom: n = {0, 1}; dist = x.y; break;
    case Wall::Top: n = {0, -1}; dist = height - x.y; break;
  }
}

}  // namespace

double speculative_reach(const BodyState& s, int k, const ContactSection& c, double dt) {
  return 0.5 * c.margin + length(s.velocity[static_cast<size_t>(k)]) * dt;
}

namespace {

/// The circle pair test on the fields of bodies a and b (both entry points below).
inline std::optional<Contact> circle_pair(Vec2 xa, double ra, Vec2 xb, double rb, int a, int b, double threshold) {
  const Vec2 d = xb - xa;
  const double rsum = ra + rb;
  const double dist2 = length_squared(d);
  // Cheap reject before the square root.
  const double reach = rsum + threshold;
  if (dist2 >= reach * reach) return std::nullopt;
  const double dist = std::sqrt(dist2);
  Contact c;
  c.key = ContactKey::pair(a, b);
  c.body_a = a;
  c.body_b = b;
  c.normal = dist > 1e-12 * rsum ? (1.0 / dist) * d : Vec2{0.0, 1.0};
  c.gap = dist - rsum;
  // Midway between the two surfaces along the normal.
  c.point = xa + (ra + 0.5 * c.gap) * c.normal;
  return c;
}

}  // namespace

std::optional<Contact> circle_circle(const BodyState& s, int a, int b, double threshold) {
  const auto ia = static_cast<size_t>(a), ib = static_cast<size_t>(b);
  return circle_pair(s.position[ia], s.radius[ia], s.position[ib], s.radius[ib], a, b, threshold);
}

std::optional<Contact> circle_circle(const CircleProbe& pa, const CircleProbe& pb, int a, int b) {
  return circle_pair(pa.centre, pa.radius, pb.centre, pb.radius, a, b, pa.spec + pb.spec);
}

std::optional<Contact> circle_wall(const BodyState& s, int k, Wall w, double width, double height,
                                   double threshold) {
  const auto i = static_cast<size_t>(k);
  const Vec2 x = s.position[i];
  const double r = s.radius[i];
  Vec2 n;
  double dist = 0;  // centre distance to the wall plane, positive inside the box
  wall_plane(x, w, width, height, n, dist);
  const double gap = dist - r;
  if (gap >= threshold) return std::nullopt;
  Contact c;
  c.key = ContactKey::wall(w, k);
  c.body_a = static_cast<int>(w);
  c.body_b = k;
  c.normal = n;
  c.gap = gap;
  c.point = x - (r + 0.5 * gap) * n;
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
