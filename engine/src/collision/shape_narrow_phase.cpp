#include "dc/engine/shape_narrow_phase.hpp"

#include <algorithm>
#include <cmath>

#include "collision/narrow_phase.hpp"
#include "det_math.hpp"

namespace dc {
namespace {

constexpr Wall kWalls[4] = {Wall::Left, Wall::Right, Wall::Bottom, Wall::Top};

void wall_plane_of(Wall w, double width, double height, Vec2& n, double& offset) {
  switch (w) {
    case Wall::Left: n = {1, 0}; offset = 0; break;
    case Wall::Right: n = {-1, 0}; offset = -width; break;
    case Wall::Bottom: n = {0, 1}; offset = 0; break;
    case Wall::Top: n = {0, -1}; offset = -height; break;
  }
}

Contact to_contact(const ContactKey& key, int a, int b, const ContactPoint& p, const ShapePose* pa,
                   const ShapePose& pb) {
  Contact c;
  c.key = key;
  c.body_a = a;
  c.body_b = b;
  c.point = p.point;
  c.normal = p.normal;
  c.gap = p.gap;
  c.anchor_a = pa ? pa->unrotate(p.on_a - pa->x) : p.on_a;
  c.anchor_b = pb.unrotate(p.on_b - pb.x);
  return c;
}

/// True when a polygon whose world box grown by `spec` is [lo, hi] has no vertex within
/// 2·spec of the wall plane dot(n, p) = offset (n an axis, into the world): its support
/// vertex lies at least (box distance + spec) from the plane, so collide_shape_plane would
/// find no point. kSlack [m] absorbs the rounding of the box (centre ± half ± spec).
bool beyond_wall_reach(Vec2 lo, Vec2 hi, Vec2 n, double offset, double spec) {
  constexpr double kSlack = 1e-6;
  const double nearest = std::min(dot(n, lo), dot(n, hi)) - offset;  // the box's nearest side
  return nearest > spec + kSlack;
}

/// The m points of one body pair or body–wall pair with their features ascending (their keys'
/// order); returns m.
int in_feature_order(int m, ContactPoint pts[2]) {
  if (m == 2 && pts[1].feature < pts[0].feature) std::swap(pts[0], pts[1]);
  return m;
}

/// Sorts by key. collide() appends the walls in key order, then the broad phase's sorted pairs,
/// each one's points in feature order (in_feature_order), so the list is normally strictly
/// increasing already: then it is left as it is (the one order any sort gives distinct keys),
/// and only otherwise sorted.
void sort_by_key(std::vector<Contact>& contacts) {
  const auto not_before = [](const Contact& x, const Contact& y) { return !(x.key < y.key); };
  if (std::adjacent_find(contacts.begin(), contacts.end(), not_before) == contacts.end()) return;
  std::sort(contacts.begin(), contacts.end(), [](const Contact& x, const Contact& y) { return x.key < y.key; });
}

}  // namespace

double shape_speculative_reach(const BodyState& s, int k, const ContactSection& c, double dt) {
  const auto i = static_cast<size_t>(k);
  const double r = speculative_reach(s, k, c, dt);
  if (s.shapes.kind[i] == ShapeKind::Circle) return r;
  return r + std::abs(s.omega[i]) * dt * s.radius[i];
}

ShapePose make_pose(const BodyState& s, int k, std::vector<Vec2>& wv, std::vector<Vec2>& wn) {
  const auto i = static_cast<size_t>(k);
  ShapePose p;
  p.kind = s.shapes.kind[i];
  p.x = s.position[i];
  p.radius = s.radius[i];
  if (p.kind != ShapeKind::Circle) det_sincos(s.angle[i], p.s, p.c);  // libm-free: same bits on every CPU
  if (p.kind == ShapeKind::Polygon) {
    const int off = s.shapes.vertex_offset[i];
    p.count = s.shapes.vertex_count(i);
    if (wv.size() < static_cast<size_t>(p.count)) wv.resize(static_cast<size_t>(p.count));
    if (wn.size() < static_cast<size_t>(p.count)) wn.resize(static_cast<size_t>(p.count));
    transform_polygon(&s.shapes.vertices[static_cast<size_t>(off)], &s.shapes.normals[static_cast<size_t>(off)],
                      p.count, p.c, p.s, p.x, wv.data(), wn.data());
    p.vertices = wv.data();
    p.normals = wn.data();
  }
  p.semi = s.shapes.semi_axes[i];
  return p;
}

void ShapeNarrowPhase::update_poses(const BodyState& s) {
  const std::size_t n = s.size();
  cos_.assign(n, 1.0);
  sin_.assign(n, 0.0);
  world_vertices_.resize(s.shapes.vertices.size());
  world_normals_.resize(s.shapes.vertices.size());
  for (std::size_t k = 0; k < n; ++k) {
    if (s.shapes.kind[k] == ShapeKind::Circle) continue;
    det_sincos(s.angle[k], sin_[k], cos_[k]);  // libm-free: same bits on every CPU
    if (s.shapes.kind[k] == ShapeKind::Polygon) {
      const auto off = static_cast<size_t>(s.shapes.vertex_offset[k]);
      transform_polygon(&s.shapes.vertices[off], &s.shapes.normals[off], s.shapes.vertex_count(k), cos_[k], sin_[k],
                        s.position[k], &world_vertices_[off], &world_normals_[off]);
    }
  }
}

ShapePose ShapeNarrowPhase::pose(const BodyState& s, int k) const {
  const auto i = static_cast<size_t>(k);
  ShapePose p;
  p.kind = s.shapes.kind[i];
  p.x = s.position[i];
  p.c = cos_[i];
  p.s = sin_[i];
  p.radius = s.radius[i];
  if (p.kind == ShapeKind::Polygon) {
    const auto off = static_cast<size_t>(s.shapes.vertex_offset[i]);
    p.vertices = &world_vertices_[off];
    p.normals = &world_normals_[off];
    p.count = s.shapes.vertex_count(i);
  }
  p.semi = s.shapes.semi_axes[i];
  return p;
}

void ShapeNarrowPhase::collide(const BodyState& s, const WorldDef& def, UniformGridBroadPhase& broad_phase,
                               std::vector<Contact>& contacts) {
  const int n = static_cast<int>(s.size());
  const double dt = def.time.dt;
  contacts.clear();
  update_poses(s);
  spec_.resize(static_cast<size_t>(n));
  lo_.resize(static_cast<size_t>(n));
  hi_.resize(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    const auto i = static_cast<size_t>(k);
    const double sp = spec_[i] = shape_speculative_reach(s, k, def.contact, dt);
    Vec2 half{s.radius[i], s.radius[i]};
    Vec2 centre = s.position[i];
    if (s.shapes.kind[i] == ShapeKind::Polygon) {
      const auto off = static_cast<size_t>(s.shapes.vertex_offset[i]);
      Vec2 l = world_vertices_[off], h = l;
      for (int v = 1; v < s.shapes.vertex_count(i); ++v) {
        const Vec2 p = world_vertices_[off + static_cast<size_t>(v)];
        l = {std::min(l.x, p.x), std::min(l.y, p.y)};
        h = {std::max(h.x, p.x), std::max(h.y, p.y)};
      }
      centre = 0.5 * (l + h);
      half = 0.5 * (h - l);
    } else if (s.shapes.kind[i] == ShapeKind::Ellipse) {
      const double a = s.shapes.semi_axes[i].x, b = s.shapes.semi_axes[i].y, c = cos_[i], sn = sin_[i];
      half = {std::sqrt(a * a * c * c + b * b * sn * sn), std::sqrt(a * a * sn * sn + b * b * c * c)};
    }
    lo_[i] = centre - half - Vec2{sp, sp};
    hi_[i] = centre + half + Vec2{sp, sp};
  }

  ContactPoint pts[2];
  for (int w = 3; w >= 0; --w) {
    if (!def.world.walls[static_cast<size_t>(w)]) continue;
    Vec2 wn;
    double off = 0;
    wall_plane_of(kWalls[w], def.world.width, def.world.height, wn, off);
    for (int k = 0; k < n; ++k) {
      const auto i = static_cast<size_t>(k);
      if (!s.shapes.is_dynamic(i)) continue;
      if (s.shapes.kind[i] == ShapeKind::Polygon && beyond_wall_reach(lo_[i], hi_[i], wn, off, spec_[i])) continue;
      if (s.shapes.kind[i] == ShapeKind::Circle) {
        if (auto c = circle_wall(s, k, kWalls[w], def.world.width, def.world.height, 2 * spec_[i]))
          contacts.push_back(*c);
        continue;
      }
      const ShapePose p = pose(s, k);
      const int m = in_feature_order(collide_shape_plane(p, wn, off, 2 * spec_[i], pts), pts);
      for (int q = 0; q < m; ++q)
        contacts.push_back(to_contact(ContactKey::wall(kWalls[w], k, pts[q].feature), static_cast<int>(kWalls[w]), k,
                                      pts[q], nullptr, p));
    }
  }

  broad_phase.find_box_pairs(lo_, hi_, pairs_);
  for (const auto& [i, j] : pairs_) {
    const bool di = s.shapes.is_dynamic(static_cast<size_t>(i)), dj = s.shapes.is_dynamic(static_cast<size_t>(j));
    if (!di && !dj) continue;
    // body_a: the non-dynamic body if there is one (its rows have no columns for it).
    const int a = di ? (dj ? i : j) : i, b = a == i ? j : i;
    const auto ia = static_cast<size_t>(a), ib = static_cast<size_t>(b);
    if (s.shapes.kind[ia] == ShapeKind::Circle && s.shapes.kind[ib] == ShapeKind::Circle) {
      if (auto c = circle_circle(s, a, b, spec_[ia] + spec_[ib])) {
        c->body_a = a;
        c->body_b = b;
        contacts.push_back(*c);
      }
      continue;
    }
    const ShapePose pa = pose(s, a), pb = pose(s, b);
    const int m = in_feature_order(collide_shapes(pa, pb, spec_[ia], spec_[ib], pts, method), pts);
    for (int q = 0; q < m; ++q)
      contacts.push_back(to_contact(ContactKey::pair(a, b, pts[q].feature), a, b, pts[q], &pa, pb));
  }
  sort_by_key(contacts);
}

}  // namespace dc
