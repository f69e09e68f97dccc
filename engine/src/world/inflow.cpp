#include "dc/engine/inflow.hpp"

#include <algorithm>
#include <cmath>

#include "dc/core/rng.hpp"

namespace dc {
namespace {

/// Emission times t_k = start + k / rate, k = 0, 1, …: how many satisfy t_k ≤ t (and < stop).
/// The 1e-9 absorbs rounding of t = step · dt (e.g. 0.3 · 50 = 14.999…).
int due_by(const InflowSection& f, double t, int total) {
  if (!f.active() || t + 1e-12 < f.start) return 0;
  const double k = std::floor((t - f.start) * f.rate + 1e-9) + 1;
  return static_cast<int>(std::min<double>(k, total));
}

}  // namespace

Inflow::Inflow(const WorldDef& def) : world_(def.world), inflow_(def.inflow) {
  for (const BodyDef& b : def.body)
    if (b.spawn > 0) delayed_.push_back(b);
  std::stable_sort(delayed_.begin(), delayed_.end(), [](const BodyDef& a, const BodyDef& b) { return a.spawn < b.spawn; });
  if (inflow_.active()) {
    // Number of k with start + k / rate < stop.
    const double span = (inflow_.stop - inflow_.start) * inflow_.rate;
    emissions_ = static_cast<int>(std::ceil(span - 1e-9));
    rng_ = std::make_unique<Rng>(def.bodies.seed ^ inflow_.seed ^ 0x1f10a7ce5eedULL);
  }
}

Inflow::~Inflow() = default;
Inflow::Inflow(Inflow&&) noexcept = default;
Inflow& Inflow::operator=(Inflow&&) noexcept = default;

Inflow::Inflow(const Inflow& o)
    : world_(o.world_), inflow_(o.inflow_), delayed_(o.delayed_), delayed_done_(o.delayed_done_),
      emissions_(o.emissions_), emitted_(o.emitted_), next_radius_(o.next_radius_) {
  if (o.rng_) {
    rng_ = std::make_unique<Rng>(0);
    rng_->restore_state(o.rng_->algorithm(), o.rng_->save_state());
  }
}

Inflow& Inflow::operator=(const Inflow& o) {
  if (this != &o) *this = Inflow(o);
  return *this;
}

bool Inflow::fits(const BodyState& s, Vec2 x, double r) const {
  if (x.x - r < 0 || x.x + r > world_.width || x.y - r < 0 || x.y + r > world_.height) return false;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double rs = r + s.radius[k];
    if (length_squared(x - s.position[k]) < rs * rs) return false;
  }
  return true;
}

int Inflow::emit(double t, BodyState& bodies) {
  if (!pending()) return 0;
  int added = 0;
  // Explicit late bodies, in spawn order; one that overlaps waits (and holds back later ones).
  while (delayed_done_ < static_cast<int>(delayed_.size())) {
    const BodyDef& b = delayed_[static_cast<std::size_t>(delayed_done_)];
    if (b.spawn > t + 1e-12 || !fits(bodies, b.position, b.radius)) break;
    bodies.add(b.position, b.radius, b.density, b.velocity, b.angle, b.omega);
    ++delayed_done_;
    ++added;
  }
  const int due = due_by(inflow_, t, emissions_);
  const auto& R = inflow_.region;
  while (emitted_ < due) {
    if (next_radius_ < 0)
      next_radius_ = inflow_.radius_max > inflow_.radius ? rng_->uniform(inflow_.radius, inflow_.radius_max)
                                                         : inflow_.radius;
    bool placed = false;
    for (int a = 0; a < inflow_.max_attempts && !placed; ++a) {
      const Vec2 x{rng_->uniform(R[0], R[2]), rng_->uniform(R[1], R[3])};
      if (!fits(bodies, x, next_radius_)) continue;
      bodies.add(x, next_radius_, inflow_.density, inflow_.velocity);
      placed = true;
    }
    if (!placed) break;  // no room now: this body and the later ones wait for the next step
    next_radius_ = -1;
    ++emitted_;
    ++added;
  }
  return added;
}

}  // namespace dc
