// make_bodies: the seeded scene generator (docs/design.md §3) and the checks on explicit circles.
#include <cmath>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include "dc/core/error.hpp"
#include "dc/core/number_text.hpp"
#include "dc/core/rng.hpp"
#include "dc/engine/shape_collide.hpp"
#include "dc/engine/shape_narrow_phase.hpp"
#include "dc/engine/world.hpp"
#include "world/spatial_order.hpp"
#include "world_def_limits.hpp"

namespace dc {
namespace {

/// A hash grid of placed circles for O(1) overlap queries while sampling.
class PlacedCircles {
 public:
  explicit PlacedCircles(double cell) : cell_(cell) {}
  void add(Vec2 x, double r) {
    centres_.push_back(x);
    radii_.push_back(r);
    grid_[key(cell_of(x.x), cell_of(x.y))].push_back(static_cast<int>(centres_.size()) - 1);
  }
  /// Index of a placed circle overlapping (x, r), or −1. Touching (distance = r_a + r_b)
  /// is not an overlap.
  [[nodiscard]] int overlapping(Vec2 x, double r) const {
    const long long ci = cell_of(x.x), cj = cell_of(x.y);
    const long long span = static_cast<long long>(std::ceil((r + max_r_) / cell_));
    for (long long j = cj - span; j <= cj + span; ++j)
      for (long long i = ci - span; i <= ci + span; ++i) {
        const auto it = grid_.find(key(i, j));
        if (it == grid_.end()) continue;
        for (int p : it->second) {
          const double rs = r + radii_[static_cast<size_t>(p)];
          if (length_squared(x - centres_[static_cast<size_t>(p)]) < rs * rs) return p;
        }
      }
    return -1;
  }
  void set_max_radius(double r) { max_r_ = r; }

 private:
  [[nodiscard]] long long cell_of(double v) const { return static_cast<long long>(std::floor(v / cell_)); }
  static long long key(long long i, long long j) { return i * 2654435761LL + j; }
  double cell_;
  double max_r_ = 0;
  std::vector<Vec2> centres_;
  std::vector<double> radii_;
  std::unordered_map<long long, std::vector<int>> grid_;
};

bool inside_box(Vec2 x, double r, const WorldSection& w) {
  return x.x - r >= 0 && x.x + r <= w.width && x.y - r >= 0 && x.y + r <= w.height;
}

std::string fmt_body(std::size_t i, const BodyDef& b) {
  std::ostringstream os;
  os << "[[body]] #" << (i + 1) << " at (" << b.position.x << ", " << b.position.y
     << ") radius " << b.radius;
  return os.str();
}

/// The order in which the generated bodies at `centres` are numbered ([bodies] order):
/// placement order, or Morton order over cells of side 2·max_r (the broad phase's cell).
std::vector<int> generated_order(const BodiesSection& g, const std::vector<Vec2>& centres, double max_r) {
  if (g.order == BodyOrder::Morton && !centres.empty()) return morton_order(centres, 2 * max_r);
  std::vector<int> order(centres.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  return order;
}

/// True when the definition has only dynamic circles: the seed's generator, unchanged.
bool circles_only(const WorldDef& def) {
  if (def.bodies.shape != BodyShape::Circle) return false;
  for (const BodyDef& b : def.body)
    if (b.shape != BodyShape::Circle || b.motion != Motion::Dynamic) return false;
  return true;
}

/// Smallest gap between bodies a and b of `s` (+inf when they do not overlap); exact.
double overlap_gap(const BodyState& s, int a, int b) {
  std::vector<Vec2> va, na, vb, nb;
  const ShapePose pa = make_pose(s, a, va, na), pb = make_pose(s, b, vb, nb);
  if (pa.kind == ShapeKind::Circle && pb.kind == ShapeKind::Circle)
    return length(pb.x - pa.x) - (pa.radius + pb.radius);
  if (length(pb.x - pa.x) >= pa.radius + pb.radius) return INFINITY;
  ContactPoint pts[2];
  const int m = collide_shapes(pa, pb, 0.0, 0.0, pts);
  double g = INFINITY;
  for (int q = 0; q < m; ++q) g = std::min(g, pts[q].gap);
  return g;
}

/// Axis-aligned box of body k: is it inside the world box?
bool shape_inside_box(const BodyState& s, int k, const WorldSection& w) {
  std::vector<Vec2> wv, wn;
  const ShapePose p = make_pose(s, k, wv, wn);
  const double tol = 1e-9 * std::max({1.0, w.width, w.height});  // rounding of a body placed on a wall
  for (const Vec2 d : {Vec2{1, 0}, Vec2{-1, 0}, Vec2{0, 1}, Vec2{0, -1}}) {
    const Vec2 q = p.support(d);
    if (q.x < -tol || q.x > w.width + tol || q.y < -tol || q.y > w.height + tol) return false;
  }
  return true;
}

/// make_bodies for definitions with shapes or static/kinematic bodies. Dynamic bodies must lie
/// inside the box; bodies may not overlap unless both are static or kinematic (a funnel may be
/// built of overlapping boxes). Generated bodies avoid everything by their bounding circle
/// (each other, explicit circles) or exactly (explicit non-circle or non-dynamic bodies).
BodyState make_shaped_bodies(const WorldDef& def) {
  const BodiesSection& g = def.bodies;
  BodyState ex;  // explicit bodies, in file order
  for (std::size_t i = 0; i < def.body.size(); ++i) {
    const BodyDef& b = def.body[i];
    if (b.spawn > 0) continue;  // enters later (Inflow; validate() allows it for dynamic circles only)
    const std::string where = "[[body]] #" + std::to_string(i + 1) + " ";
    const ShapeDef sd = build_shape(b.shape, b.radius, b.size, b.sides, b.vertices, b.semi_axes, where);
    ex.add_shaped(sd, b.motion, b.position, b.density, b.velocity, b.angle, b.omega, b.pivot.has_value(),
                  b.pivot.value_or(Vec2{}));
  }
  if (ex.shapes.empty()) ex.shapes.add_circles(0);
  const int ne = static_cast<int>(ex.size());
  for (int i = 0; i < ne; ++i) {
    const auto ii = static_cast<size_t>(i);
    if (ex.shapes.is_dynamic(ii) && !shape_inside_box(ex, i, def.world))
      throw ConfigError("[[body]] #" + std::to_string(i + 1) + " (" + shape_kind_name(ex.shapes.kind[ii]) +
                        ") lies (partly) outside the box [0, " + g_text(def.world.width) + "] x [0, " +
                        g_text(def.world.height) + "]");
    for (int j = 0; j < i; ++j) {
      if (!ex.shapes.is_dynamic(ii) && !ex.shapes.is_dynamic(static_cast<size_t>(j))) continue;
      const double tol = 1e-9 * std::max(1.0, ex.radius[ii] + ex.radius[static_cast<size_t>(j)]);
      if (overlap_gap(ex, j, i) < -tol)
        throw ConfigError("[[body]] #" + std::to_string(i + 1) + " overlaps [[body]] #" + std::to_string(j + 1));
    }
  }

  const ShapeDef gen = build_shape(g.shape, g.radius, g.size, g.sides, g.vertices, g.semi_axes, "[bodies] ");
  double max_r = g.count > 0 ? std::max(gen.radius, g.radius_max) : 0.0;
  for (int i = 0; i < ne; ++i)
    if (ex.shapes.kind[static_cast<size_t>(i)] == ShapeKind::Circle && ex.shapes.is_dynamic(static_cast<size_t>(i)))
      max_r = std::max(max_r, ex.radius[static_cast<size_t>(i)]);
  PlacedCircles placed(std::max(2 * max_r, 1e-9));
  placed.set_max_radius(max_r);
  std::vector<int> exact;  // explicit bodies checked exactly
  for (int i = 0; i < ne; ++i) {
    const auto ii = static_cast<size_t>(i);
    if (ex.shapes.kind[ii] == ShapeKind::Circle && ex.shapes.is_dynamic(ii)) placed.add(ex.position[ii], ex.radius[ii]);
    else exact.push_back(i);
  }
  BodyState probe = ex;  // explicit bodies + the candidate as the last body
  probe.add_shaped(gen, Motion::Dynamic, {}, g.density);
  const int cand = ne;

  // [bodies] region applies to shaped bodies as to circles; a radius spread does not.
  const auto& R = g.region;
  const bool uniform = !(R[0] == 0 && R[1] == 0 && R[2] == 0 && R[3] == 0);
  if (g.count > 0 && g.radius_max > g.radius && gen.kind != ShapeKind::Circle)
    throw ConfigError("[bodies] radius_max: a radius spread applies to shape = \"circle\" only");
  const bool spread = g.radius_max > g.radius;
  BodyState s;
  s.reserve(static_cast<std::size_t>(g.count) + def.body.size());
  Rng rng(g.seed);
  const bool round = gen.kind == ShapeKind::Circle;
  struct Placed {
    ShapeDef shape;
    Vec2 x;
    double theta;
  };
  std::vector<Placed> placements;  // in placement order; numbered by [bodies] order below
  placements.reserve(static_cast<std::size_t>(g.count));
  for (int k = 0; k < g.count; ++k) {
    bool ok = false;
    // As in the circle generator: the radius is drawn before the position (polydisperse).
    const ShapeDef cur = spread ? make_circle(rng.uniform(g.radius, g.radius_max)) : gen;
    probe.radius[static_cast<size_t>(cand)] = cur.radius;
    for (int attempt = 0; attempt < g.max_attempts; ++attempt) {
      const Vec2 x = uniform ? Vec2{rng.uniform(R[0], R[2]), rng.uniform(R[1], R[3])}
                             : Vec2{g.mean.x + rng.gaussian(g.sigma), g.mean.y + rng.gaussian(g.sigma)};
      if (!inside_box(x, cur.radius, def.world) || placed.overlapping(x, cur.radius) >= 0) continue;
      const double theta = round ? 0.0 : rng.uniform(0.0, 2 * std::numbers::pi);
      probe.position[static_cast<size_t>(cand)] = x;
      probe.angle[static_cast<size_t>(cand)] = theta;
      bool clear = true;
      for (const int e : exact)
        if (length(x - ex.position[static_cast<size_t>(e)]) < cur.radius + ex.radius[static_cast<size_t>(e)] &&
            overlap_gap(probe, e, cand) < 0) { clear = false; break; }
      if (!clear) continue;
      placed.add(x, cur.radius);
      placements.push_back({cur, x, theta});
      ok = true;
      break;
    }
    if (!ok)
      throw ConfigError("[bodies] could not place body " + std::to_string(k + 1) + " of " + std::to_string(g.count) +
                        " without overlap after " + std::to_string(g.max_attempts) +
                        " attempts: lower count or size, or raise sigma or the box size");
  }
  std::vector<Vec2> centres;
  for (const Placed& q : placements) centres.push_back(q.x);
  for (const int k : generated_order(g, centres, max_r)) {
    const Placed& q = placements[static_cast<size_t>(k)];
    s.add_shaped(q.shape, Motion::Dynamic, q.x, g.density, {}, q.theta);
  }
  if (s.shapes.empty()) s.shapes.add_circles(0);
  for (int i = 0; i < ne; ++i) {
    const auto ii = static_cast<size_t>(i);
    s.position.push_back(ex.position[ii]); s.angle.push_back(ex.angle[ii]);
    s.velocity.push_back(ex.velocity[ii]); s.omega.push_back(ex.omega[ii]);
    s.radius.push_back(ex.radius[ii]); s.density.push_back(ex.density[ii]);
    s.mass.push_back(ex.mass[ii]); s.inertia.push_back(ex.inertia[ii]);
    s.inv_mass.push_back(ex.inv_mass[ii]); s.inv_inertia.push_back(ex.inv_inertia[ii]);
  }
  // Shape table: the generated bodies' entries, then the explicit ones'.
  ShapeTable t;
  for (std::size_t k = 0; k < s.size() - static_cast<size_t>(ne); ++k) t.add(gen, Motion::Dynamic);
  const ShapeTable& e = ex.shapes;
  for (int i = 0; i < ne; ++i) {
    const auto ii = static_cast<size_t>(i);
    ShapeDef sd;
    sd.kind = e.kind[ii];
    sd.radius = ex.radius[ii];
    sd.semi_axes = e.semi_axes[ii];
    sd.vertices.assign(e.vertices.begin() + e.vertex_offset[ii], e.vertices.begin() + e.vertex_offset[ii + 1]);
    t.add(sd, e.motion[ii], e.has_pivot[ii] != 0, e.pivot[ii]);
  }
  s.shapes = std::move(t);
  return s;
}

}  // namespace

BodyState make_bodies(const WorldDef& def) {
  def.validate();
  validate_generated_count(def);  // before placing: refuse at once what cannot fit
  if (!circles_only(def)) return make_shaped_bodies(def);
  const BodiesSection& g = def.bodies;
  double max_r = g.count > 0 ? std::max(g.radius, g.radius_max) : 0.0;
  for (const BodyDef& b : def.body) max_r = std::max(max_r, b.radius);
  const bool spread = g.radius_max > g.radius;
  const auto& R = g.region;
  const bool uniform = !(R[0] == 0 && R[1] == 0 && R[2] == 0 && R[3] == 0);
  PlacedCircles placed(std::max(2 * max_r, 1e-9));
  placed.set_max_radius(max_r);

  // Explicit circles first (they are fixed), so generated ones avoid them. Circles that
  // enter later ([[body]] spawn > 0) are only checked against the box here (Inflow adds them).
  for (std::size_t i = 0; i < def.body.size(); ++i) {
    const BodyDef& b = def.body[i];
    if (!inside_box(b.position, b.radius, def.world))
      throw ConfigError(fmt_body(i, b) + " lies (partly) outside the box [0, " +
                        g_text(def.world.width) + "] x [0, " +
                        g_text(def.world.height) + "]");
    if (b.spawn > 0) continue;
    const int o = placed.overlapping(b.position, b.radius);
    if (o >= 0)
      throw ConfigError(fmt_body(i, b) + " overlaps [[body]] #" + std::to_string(o + 1));
    placed.add(b.position, b.radius);
  }

  BodyState s;
  s.reserve(static_cast<std::size_t>(g.count) + def.body.size());
  Rng rng(g.seed);
  std::vector<Vec2> centres;  // generated circles in placement order; numbered by [bodies] order below
  std::vector<double> radii;
  for (int k = 0; k < g.count; ++k) {
    bool ok = false;
    // Without radius_max / region no extra numbers are drawn: circle scenes stay bit-identical.
    const double r = spread ? rng.uniform(g.radius, g.radius_max) : g.radius;
    for (int attempt = 0; attempt < g.max_attempts; ++attempt) {
      const Vec2 x = uniform ? Vec2{rng.uniform(R[0], R[2]), rng.uniform(R[1], R[3])}
                             : Vec2{g.mean.x + rng.gaussian(g.sigma), g.mean.y + rng.gaussian(g.sigma)};
      if (!inside_box(x, r, def.world) || placed.overlapping(x, r) >= 0) continue;
      placed.add(x, r);
      centres.push_back(x);
      radii.push_back(r);
      ok = true;
      break;
    }
    if (!ok)
      throw ConfigError("[bodies] could not place circle " + std::to_string(k + 1) + " of " +
                        std::to_string(g.count) + " without overlap after " +
                        std::to_string(g.max_attempts) +
                        " attempts: lower count or radius, or raise sigma or the box size");
  }
  for (const int k : generated_order(g, centres, max_r))
    s.add(centres[static_cast<size_t>(k)], radii[static_cast<size_t>(k)], g.density);
  for (const BodyDef& b : def.body)
    if (!(b.spawn > 0)) s.add(b.position, b.radius, b.density, b.velocity, b.angle, b.omega);
  return s;
}

}  // namespace dc
