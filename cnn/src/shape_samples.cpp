#include "dc/cnn/shape_samples.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "dc/core/error.hpp"

namespace dc {

namespace {

constexpr int kRoundVertices = 16;
constexpr double kPi = 3.14159265358979323846;

/// (cos φ_i, sin φ_i), φ_i = 2πi/16, from the exact first-octant values by symmetry (no libm:
/// the samples are the same bits on every CPU, docs/reproducibility.md).
constexpr std::array<Vec2, kRoundVertices> unit_16gon() {
  constexpr double c[5] = {1.0, 0.92387953251128674, 0.70710678118654752, 0.38268343236508977, 0.0};
  std::array<Vec2, kRoundVertices> v{};
  for (int i = 0; i < kRoundVertices; ++i) {
    const int q = i / 4, r = i % 4;  // quadrant q, step r within it
    const double cr = c[r], sr = c[4 - r];
    const Vec2 base{cr, sr};  // angle r·π/8
    // rotate by q·π/2
    v[static_cast<std::size_t>(i)] = q == 0 ? base : q == 1 ? Vec2{-sr, cr} : q == 2 ? Vec2{-cr, -sr} : Vec2{sr, -cr};
  }
  return v;
}

constexpr std::array<Vec2, kRoundVertices> kUnit16 = unit_16gon();

/// Appends the m² sub-triangle centroids of triangle (a, b, c), each weighted `scale`·|T|/m².
void append_triangle(Vec2 a, Vec2 b, Vec2 c, double spacing, double scale, std::vector<AreaSample>& out) {
  const Vec2 e1 = b - a, e2 = c - a;
  const double area = 0.5 * cross(e1, e2);
  if (!(area > 0)) return;  // degenerate fan triangle (cannot happen for a validated polygon)
  const double longest = std::max({length(e1), length(e2), length(c - b)});
  const int m = std::clamp(static_cast<int>(std::ceil(longest / spacing)), 1, kMaxSubdivision);
  const double w = scale * area / (static_cast<double>(m) * m);
  const double inv = 1.0 / (3.0 * m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; i + j < m; ++j) {
      out.push_back({a + ((3 * i + 1) * inv) * e1 + ((3 * j + 1) * inv) * e2, w});
      if (i + j <= m - 2) out.push_back({a + ((3 * i + 2) * inv) * e1 + ((3 * j + 2) * inv) * e2, w});
    }
}

/// Fan of a convex CCW polygon around the origin; weights scaled by `scale`.
void append_fan(const Vec2* v, int n, double spacing, double scale, std::vector<AreaSample>& out) {
  for (int i = 0; i < n; ++i) append_triangle({0.0, 0.0}, v[i], v[(i + 1) % n], spacing, scale, out);
}

/// The inscribed 16-gon of an ellipse (a, b), weights scaled to the true area π a b.
void append_round(Vec2 semi, double spacing, std::vector<AreaSample>& out) {
  std::array<Vec2, kRoundVertices> v{};
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = {semi.x * kUnit16[i].x, semi.y * kUnit16[i].y};
  // 16-gon area = ½ Σ v_i × v_{i+1} = 8 a b sin(π/8); scale to π a b.
  constexpr double kAreaRatio = kPi / (8 * 0.38268343236508977);
  append_fan(v.data(), kRoundVertices, spacing, kAreaRatio, out);
}

}  // namespace

void append_area_samples(const BodyState& bodies, std::size_t k, double spacing, std::vector<AreaSample>& out) {
  if (!(spacing > 0) || !std::isfinite(spacing))
    throw InvalidArgument("append_area_samples: spacing must be positive and finite, got " + std::to_string(spacing));
  const ShapeTable& t = bodies.shapes;
  if (t.empty() || t.kind[k] == ShapeKind::Circle) {
    const double r = bodies.radius[k];
    append_round({r, r}, spacing, out);
  } else if (t.kind[k] == ShapeKind::Ellipse) {
    append_round(t.semi_axes[k], spacing, out);
  } else {
    append_fan(t.vertices.data() + t.vertex_offset[k], t.vertex_count(k), spacing, 1.0, out);
  }
}

Vec2 body_frame_nematic(const BodyState& bodies, std::size_t k) {
  const ShapeTable& t = bodies.shapes;
  if (t.empty() || t.kind[k] == ShapeKind::Circle) return {0.0, 0.0};
  double jxx = 0, jyy = 0, jxy = 0;
  if (t.kind[k] == ShapeKind::Ellipse) {
    const Vec2 s = t.semi_axes[k];  // the common factor A/4 cancels in q
    jxx = s.x * s.x;
    jyy = s.y * s.y;
  } else {
    const Vec2* v = t.vertices.data() + t.vertex_offset[k];
    const int n = t.vertex_count(k);
    for (int i = 0; i < n; ++i) {
      const Vec2 a = v[i], b = v[(i + 1) % n];
      const double c = cross(a, b);
      jxx += c * (a.x * a.x + a.x * b.x + b.x * b.x) / 12;
      jyy += c * (a.y * a.y + a.y * b.y + b.y * b.y) / 12;
      jxy += c * (a.x * b.y + 2 * a.x * a.y + 2 * b.x * b.y + b.x * a.y) / 24;
    }
  }
  const double trace = jxx + jyy;
  if (!(trace > 0)) return {0.0, 0.0};
  const Vec2 q{(jxx - jyy) / trace, 2 * jxy / trace};
  if (length(q) < 1e-12) return {0.0, 0.0};  // isotropic (regular polygon): rounding only
  return q;
}

}  // namespace dc
