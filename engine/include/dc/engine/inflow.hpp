#pragma once
// Bodies that enter a world during a run (docs/scenes.md, "Bodies added during a run"):
//   * [[body]] entries with spawn > 0 (e.g. the impactor of scenes/impact.toml), and
//   * the continuous [inflow]: circles emitted at `rate` per second, at times
//     t_k = start + k / rate for every t_k < stop, at uniformly random positions in `region`
//     that overlap no body and no wall (rejection-sampled, seeded from [bodies] seed xor
//     [inflow] seed), with the given velocity and body keys.
// World calls emit(t) at construction (t = 0) and after every integrate (t = the new time).
// Everything due by t is appended to the body state, so body indices stay stable (new
// bodies get the next indices: builtin's persistent keys, trajectories and warm starters
// keep working). A body that finds no free spot within max_attempts tries waits for the
// next step (an overlapping [[body]] waits too), so the run is deterministic.
// A world without spawned bodies and without inflow never draws a number here.
#include <cstdint>
#include <memory>
#include <vector>

#include "dc/engine/body_state.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {

class Rng;

class Inflow {
 public:
  explicit Inflow(const WorldDef& def);
  ~Inflow();
  Inflow(Inflow&&) noexcept;
  Inflow& operator=(Inflow&&) noexcept;
  Inflow(const Inflow& other);  ///< copies the placement stream's state
  Inflow& operator=(const Inflow& other);

  /// Appends every body due at time t [s] that fits; returns how many were added.
  int emit(double t, BodyState& bodies);

  /// Bodies this component will ever add (explicit spawns + inflow emissions).
  [[nodiscard]] int total() const { return static_cast<int>(delayed_.size()) + emissions_; }
  /// Bodies added so far.
  [[nodiscard]] int added() const { return delayed_done_ + emitted_; }
  /// False when nothing is pending (no spawn and no inflow, or all of it already added).
  [[nodiscard]] bool pending() const { return added() < total(); }

 private:
  bool fits(const BodyState& bodies, Vec2 x, double r) const;

  WorldSection world_;
  InflowSection inflow_;
  std::vector<BodyDef> delayed_;   ///< [[body]] with spawn > 0, in spawn order (stable)
  int delayed_done_ = 0;
  int emissions_ = 0;              ///< number of emission times t_k < stop
  int emitted_ = 0;
  double next_radius_ = -1;        ///< radius drawn for the body waiting to be placed (< 0: none)
  std::unique_ptr<Rng> rng_;       ///< only with inflow
};

}  // namespace dc
