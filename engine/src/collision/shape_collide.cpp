// Narrow phase of non-circle shapes (shape_collide.hpp). libccd glue in ccd_narrow.cpp.
#include "dc/engine/shape_collide.hpp"

#include <algorithm>
#include <cmath>

#include "det_math.hpp"

namespace dc {
namespace {

Vec2 normalized(Vec2 v) {
  const double l = length(v);
  return l > 0 ? (1.0 / l) * v : Vec2{0.0, 1.0};
}

/// Feature id of a polygon–polygon point: which face was the reference (flip: b's), whether
/// the point is an incident vertex (type 0) or a clip against a reference side plane (type 1),
/// and the two indices. +1 keeps it distinct from a single-point contact's feature 0.
int pack_feature(bool flip, int type, int ref_index, int inc_index) {
  return 1 + ((flip ? 1 : 0) << 11) + (type << 10) + (ref_index << 5) + inc_index;
}

struct ClipVertex {
  Vec2 p;
  int type = 0;  // 0: incident vertex `index`; 1: clipped at reference vertex `index`
  int index = 0;
  int other = 0;  // type 1: the incident edge
};

/// Keeps the part of the points `in` (1 or 2: a segment or a point) with dot(n, p) ≤ offset
/// (Sutherland–Hodgman on a segment, Box2D's b2ClipSegmentToLine). A point up to `eps` outside
/// is kept as it is: exactly aligned faces (a stack) would otherwise flip between keeping the
/// incident vertex and making a clip point at the same place, changing the feature id (and
/// losing the builtin warm start) from step to step. Returns the number of points kept.
int clip_points(const ClipVertex* in, int count, ClipVertex out[2], Vec2 n, double offset, double eps,
                int ref_vertex, int inc_edge) {
  int k = 0;
  if (count == 1) {
    if (dot(n, in[0].p) - offset <= eps) out[k++] = in[0];
    return k;
  }
  const double d0 = dot(n, in[0].p) - offset, d1 = dot(n, in[1].p) - offset;
  const bool in0 = d0 <= eps, in1 = d1 <= eps;
  if (in0) out[k++] = in[0];
  if (in1) out[k++] = in[1];
  if (in0 != in1 && d0 * d1 < 0) {
    const double t = d0 / (d0 - d1);
    out[k].p = in[0].p + t * (in[1].p - in[0].p);
    out[k].type = 1;
    out[k].index = ref_vertex;
    out[k].other = inc_edge;
    ++k;
  }
  return k;
}

/// Clipping of the incident face of I against reference face r of R (flip: R is b).
int clip_manifold(const ShapePose& a, const ShapePose& b, bool flip, int r, double threshold, ContactPoint out[2]);

/// Reference face from libccd's normal n (a → b): the face of a most aligned with n, or of b
/// with −n when clearly better aligned (a stable choice keeps feature ids, and so the builtin
/// warm start, from flickering between nearly equal faces).
int polygon_manifold(const ShapePose& a, const ShapePose& b, Vec2 n, double threshold, ContactPoint out[2]) {
  int ia = 0, ib = 0;
  double da = -2, db = -2;
  for (int i = 0; i < a.count; ++i) {
    const double d = dot(a.normals[i], n);
    if (d > da) { da = d; ia = i; }
  }
  for (int j = 0; j < b.count; ++j) {
    const double d = -dot(b.normals[j], n);
    if (d > db) { db = d; ib = j; }
  }
  const bool flip = db > da + 1e-3;
  return clip_manifold(a, b, flip, flip ? ib : ia, threshold, out);
}

/// Largest separation of b from the faces of a (Box2D's b2FindMaxSeparation): over the edges
/// i of a, min_j n_i·(w_j − v_i). Sets `edge` to the maximising edge.
double max_separation(const ShapePose& a, const ShapePose& b, int& edge) {
  double best = -INFINITY;
  for (int i = 0; i < a.count; ++i) {
    const Vec2 n = a.normals[i], v = a.vertices[i];
    double si = INFINITY;
    for (int j = 0; j < b.count; ++j) si = std::min(si, dot(n, b.vertices[j] - v));
    if (si > best) { best = si; edge = i; }
  }
  return best;
}

/// Polygon–polygon by the separating-axis test (exact for convex polygons, Box2D's
/// b2CollidePolygons): the reference face is the face of largest separation (b's only when it
/// is larger by 0.5 mm, for a stable choice), then the same clipping.
int polygon_polygon_sat(const ShapePose& a, const ShapePose& b, double threshold, ContactPoint out[2]) {
  int ea = 0, eb = 0;
  const double sa = max_separation(a, b, ea);
  if (sa >= threshold) return 0;
  const double sb = max_separation(b, a, eb);
  if (sb >= threshold) return 0;
  const bool flip = sb > sa + 5e-4;
  return clip_manifold(a, b, flip, flip ? eb : ea, threshold, out);
}

int clip_manifold(const ShapePose& a, const ShapePose& b, bool flip, int r, double threshold, ContactPoint out[2]) {
  const ShapePose& R = flip ? b : a;
  const ShapePose& I = flip ? a : b;
  const Vec2 nr = R.normals[r];
  int k = 0;
  double dk = 2;
  for (int j = 0; j < I.count; ++j) {
    const double d = dot(I.normals[j], nr);
    if (d < dk) { dk = d; k = j; }
  }
  const int k2 = (k + 1) % I.count, r2 = (r + 1) % R.count;
  const Vec2 v1 = R.vertices[r], v2 = R.vertices[r2];
  const Vec2 t = normalized(v2 - v1);
  const double eps = 1e-4 * (a.radius + b.radius);
  ClipVertex inc[2] = {{I.vertices[k], 0, k, 0}, {I.vertices[k2], 0, k2, 0}};
  ClipVertex c1[2], c2[2];
  const int n1 = clip_points(inc, 2, c1, -t, -dot(t, v1), eps, r, k);
  const int n2 = n1 > 0 ? clip_points(c1, n1, c2, t, dot(t, v2), eps, r2, k) : 0;
  int m = 0;
  for (int q = 0; q < n2; ++q) {
    const ClipVertex& cv = c2[q];
    const double sep = dot(nr, cv.p - v1);
    if (sep >= threshold) continue;
    ContactPoint& cp = out[m++];
    cp.gap = sep;
    cp.normal = flip ? -nr : nr;
    cp.point = cv.p - 0.5 * sep * nr;
    const Vec2 on_ref = cv.p - sep * nr;
    cp.on_a = flip ? cv.p : on_ref;
    cp.on_b = flip ? on_ref : cv.p;
    cp.feature = cv.type == 0 ? pack_feature(flip, 0, r, cv.index) : pack_feature(flip, 1, cv.index, cv.other);
  }
  return m;
}

/// Support-based separation of a and b along n (a → b): n·(s_b(−n) − s_a(n)). Over all unit n
/// its maximum is the signed distance (minus the penetration depth when they overlap).
double separation(const ShapePose& a, const ShapePose& b, Vec2 n) { return dot(n, b.support(-n) - a.support(n)); }

/// n turned counter-clockwise by t [rad] (det_sincos: the same bits on every CPU).
Vec2 turned(Vec2 n, double t) {
  double c = 1, s = 0;
  det_sincos(t, s, c);
  return {c * n.x - s * n.y, s * n.x + c * n.y};
}

/// Polishes libccd's unit normal n (EPA and MPR stop at a tolerance, ~1e-5 m of gap on curved
/// shapes) by maximising separation(R(φ) n) over the turn φ: golden-section search on ±0.05
/// rad, 40 steps (the bracket shrinks to ~1e-9 rad). Local, so it keeps the minimum libccd
/// found.
Vec2 refine_normal(const ShapePose& a, const ShapePose& b, Vec2 n) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = -0.05, hi = 0.05;
  auto f = [&](double phi) { return separation(a, b, turned(n, phi)); };
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < 40; ++it) {
    if (f1 < f2) {
      lo = x1; x1 = x2; f1 = f2; x2 = lo + g * (hi - lo); f2 = f(x2);
    } else {
      hi = x2; x2 = x1; f2 = f1; x1 = hi - g * (hi - lo); f1 = f(x1);
    }
  }
  const Vec2 m = turned(n, 0.5 * (lo + hi));
  return separation(a, b, m) >= separation(a, b, n) ? m : n;
}

/// One point from a normal n (a → b): witnesses are the support points along ±n; the point
/// lies on the smoother surface (a polygon's support along n is a vertex, not the foot).
int single_point(const ShapePose& a, const ShapePose& b, Vec2 n_ccd, double threshold, ContactPoint out[1]) {
  const Vec2 n = refine_normal(a, b, n_ccd);
  const Vec2 pa = a.support(n), pb = b.support(-n);
  const double gap = dot(n, pb - pa);
  if (gap >= threshold) return 0;
  ContactPoint& cp = out[0];
  cp.normal = n;
  cp.gap = gap;
  if (a.kind == ShapeKind::Polygon && b.kind != ShapeKind::Polygon) {
    cp.on_b = pb;
    cp.on_a = pb - gap * n;
  } else {
    cp.on_a = pa;
    cp.on_b = pa + gap * n;
  }
  cp.point = cp.on_a + 0.5 * gap * n;
  cp.feature = 0;
  return 1;
}

}  // namespace

Vec2 ShapePose::support(Vec2 d) const {
  switch (kind) {
    case ShapeKind::Circle: return x + radius * normalized(d);
    case ShapeKind::Polygon: {
      int best = 0;
      double bd = dot(d, vertices[0]);
      for (int i = 1; i < count; ++i) {
        const double v = dot(d, vertices[i]);
        if (v > bd) { bd = v; best = i; }
      }
      return vertices[best];
    }
    case ShapeKind::Ellipse: {
      // s(d) = x + R D² d' / √(d'ᵀ D² d'),  d' = Rᵀ d,  D = diag(a, b)
      const Vec2 dl = unrotate(d);
      const Vec2 q{semi.x * semi.x * dl.x, semi.y * semi.y * dl.y};
      const double den = std::sqrt(semi.x * semi.x * dl.x * dl.x + semi.y * semi.y * dl.y * dl.y);
      return den > 0 ? x + rotate((1.0 / den) * q) : x;
    }
  }
  return x;
}

void transform_polygon(const Vec2* local, const Vec2* local_normals, int count, double c, double s, Vec2 x,
                       Vec2* world, Vec2* world_normals) {
  for (int i = 0; i < count; ++i) {
    const Vec2 v = local[i], m = local_normals[i];
    world[i] = x + Vec2{c * v.x - s * v.y, s * v.x + c * v.y};
    world_normals[i] = Vec2{c * m.x - s * m.y, s * m.x + c * m.y};
  }
}

int collide_circle_polygon(const ShapePose& circle, const ShapePose& poly, double threshold, bool circle_is_a,
                           ContactPoint out[1]) {
  // Box2D's b2CollidePolygonAndCircle: the edge of maximum separation, then its Voronoi regions.
  const Vec2 c = circle.x;
  const double r = circle.radius;
  int e = 0;
  double sep = -INFINITY;
  for (int i = 0; i < poly.count; ++i) {
    const double si = dot(poly.normals[i], c - poly.vertices[i]);
    if (si > sep) { sep = si; e = i; }
  }
  if (sep - r >= threshold) return 0;
  const Vec2 v1 = poly.vertices[e], v2 = poly.vertices[(e + 1) % poly.count];
  Vec2 n;       // from the polygon to the circle
  Vec2 on_poly;
  double dist;  // centre to polygon surface
  if (sep <= 0) {
    n = poly.normals[e];
    dist = sep;
    on_poly = c - sep * n;
  } else if (dot(c - v1, v2 - v1) <= 0) {
    dist = length(c - v1);
    n = normalized(c - v1);
    on_poly = v1;
  } else if (dot(c - v2, v1 - v2) <= 0) {
    dist = length(c - v2);
    n = normalized(c - v2);
    on_poly = v2;
  } else {
    n = poly.normals[e];
    dist = sep;
    on_poly = c - sep * n;
  }
  const double gap = dist - r;
  if (gap >= threshold) return 0;
  ContactPoint& cp = out[0];
  const Vec2 on_circle = c - r * n;
  cp.gap = gap;
  cp.normal = circle_is_a ? -n : n;
  cp.on_a = circle_is_a ? on_circle : on_poly;
  cp.on_b = circle_is_a ? on_poly : on_circle;
  cp.point = on_poly + 0.5 * gap * n;
  cp.feature = 0;
  return 1;
}

int collide_shape_plane(const ShapePose& k, Vec2 n, double offset, double threshold, ContactPoint out[2]) {
  // Plane: dot(n, p) = offset, n into the box. The deepest points are the support along −n.
  if (k.kind == ShapeKind::Polygon) {
    int e = 0;
    double de = 2;
    for (int i = 0; i < k.count; ++i) {
      const double d = dot(k.normals[i], n);
      if (d < de) { de = d; e = i; }
    }
    int m = 0;
    for (const int i : {e, (e + 1) % k.count}) {
      const Vec2 p = k.vertices[i];
      const double gap = dot(n, p) - offset;
      if (gap >= threshold) continue;
      ContactPoint& cp = out[m++];
      cp.gap = gap;
      cp.normal = n;
      cp.on_b = p;
      cp.on_a = p - gap * n;
      cp.point = p - 0.5 * gap * n;
      cp.feature = 1 + i;
    }
    return m;
  }
  const Vec2 p = k.support(-n);
  const double gap = dot(n, p) - offset;
  if (gap >= threshold) return 0;
  ContactPoint& cp = out[0];
  cp.gap = gap;
  cp.normal = n;
  cp.on_b = p;
  cp.on_a = p - gap * n;
  cp.point = p - 0.5 * gap * n;
  cp.feature = 0;
  return 1;
}

int collide_shapes(const ShapePose& a, const ShapePose& b, double inflate_a, double inflate_b, ContactPoint out[2],
                   CcdMethod method, bool polygon_sat) {
  const double threshold = inflate_a + inflate_b;
  if (polygon_sat && a.kind == ShapeKind::Polygon && b.kind == ShapeKind::Polygon)
    return polygon_polygon_sat(a, b, threshold, out);
  if (a.kind == ShapeKind::Circle && b.kind == ShapeKind::Polygon)
    return collide_circle_polygon(a, b, threshold, true, out);
  if (a.kind == ShapeKind::Polygon && b.kind == ShapeKind::Circle)
    return collide_circle_polygon(b, a, threshold, false, out);
  // libccd needs the inflated shapes to overlap by more than its tolerance: at exact touching
  // (depth 0) it returns an arbitrary direction. So inflate by at least 1e-4 of the size; the
  // points are still filtered by the pair's own threshold.
  const double floor = 1e-4 * (a.radius + b.radius);
  Vec2 n;
  double gap = 0;
  if (!ccd_normal_gap(a, b, std::max(inflate_a, floor), std::max(inflate_b, floor), method, n, gap)) return 0;
  if (a.kind == ShapeKind::Polygon && b.kind == ShapeKind::Polygon) {
    const int m = polygon_manifold(a, b, n, threshold, out);
    if (m > 0) return m;
  }
  return single_point(a, b, n, threshold, out);
}

}  // namespace dc
