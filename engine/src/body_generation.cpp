// make_bodies: the seeded scene generator (DESIGN §3) and the checks on explicit circles.
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "dc/engine/error.hpp"
#include "dc/engine/rng.hpp"
#include "dc/engine/world.hpp"

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

}  // namespace

BodyState make_bodies(const WorldDef& def) {
  def.validate();
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
                        std::to_string(def.world.width) + "] x [0, " +
                        std::to_string(def.world.height) + "]");
    if (b.spawn > 0) continue;
    const int o = placed.overlapping(b.position, b.radius);
    if (o >= 0)
      throw ConfigError(fmt_body(i, b) + " overlaps [[body]] #" + std::to_string(o + 1));
    placed.add(b.position, b.radius);
  }

  BodyState s;
  s.reserve(static_cast<std::size_t>(g.count) + def.body.size());
  Rng rng(g.seed);
  for (int k = 0; k < g.count; ++k) {
    bool ok = false;
    // Without radius_max / region no extra numbers are drawn: circle scenes stay bit-identical.
    const double r = spread ? rng.uniform(g.radius, g.radius_max) : g.radius;
    for (int attempt = 0; attempt < g.max_attempts; ++attempt) {
      const Vec2 x = uniform ? Vec2{rng.uniform(R[0], R[2]), rng.uniform(R[1], R[3])}
                             : Vec2{g.mean.x + rng.gaussian(g.sigma), g.mean.y + rng.gaussian(g.sigma)};
      if (!inside_box(x, r, def.world) || placed.overlapping(x, r) >= 0) continue;
      placed.add(x, r);
      s.add(x, r, g.density);
      ok = true;
      break;
    }
    if (!ok)
      throw ConfigError("[bodies] could not place circle " + std::to_string(k + 1) + " of " +
                        std::to_string(g.count) + " without overlap after " +
                        std::to_string(g.max_attempts) +
                        " attempts: lower count or radius, or raise sigma or the box size");
  }
  for (const BodyDef& b : def.body)
    if (!(b.spawn > 0)) s.add(b.position, b.radius, b.density, b.velocity, b.angle, b.omega);
  return s;
}

}  // namespace dc
