#pragma once
// Records a simulation (e.g. `deepcontact simulate --out`) and writes the HDF5 trajectory
// (layout: docs/formats.md, "Trajectory"). State k = 0..S is the state before step k+1;
// the contacts and λ of step k (solved from state k) are rows
// [step_offset[k], step_offset[k+1]) of the /contacts datasets (step_offset[S] = C).
// Bodies that enter during the run (inflow.hpp) make n the final count; their rows of the
// states before they existed are NaN.
#include <cstdint>
#include <string>
#include <vector>

#include "dc/engine/world.hpp"

namespace dc {

/// Version of the trajectory layout written (2: shape table /bodies/shape/*, /contacts/feature).
inline constexpr std::int32_t kTrajectoryFormatVersion = 2;

class TrajectoryRecorder {
 public:
  /// Records state 0 of `world`; the file's `start_step` is world.step_index() (a recording
  /// that starts after a warm-up keeps its true time).
  explicit TrajectoryRecorder(const World& world);
  /// Reserves memory for `steps` more steps of the body state (simulate knows its step
  /// count), so recording never re-allocates and copies the whole history (the contacts,
  /// whose number is not known ahead, still grow geometrically).
  void reserve_steps(int steps);
  /// After world.step(): records the step's contacts (with solved λ), solver figures, the
  /// step's profile (report.profile plus the time of this call) and the new state.
  void record_step(const World& world, const StepReport& report);
  /// Writes the file atomically (tmp + rename). `scene` is the TOML text of the scene.
  void write(const std::string& path, const std::string& scene, const std::string& warmstart) const;

  [[nodiscard]] int steps() const { return static_cast<int>(sweeps_.size()); }
  [[nodiscard]] std::size_t contacts() const { return body_a_.size(); }
  /// Columns of /solver/profile, in order (docs/formats.md); values in seconds.
  static constexpr const char* kProfileColumns =
      "collide,assemble,warm_start,solve,integrate,record,broad_phase";
  static constexpr int kProfileWidth = 7;
  /// Row-major (steps × kProfileWidth) per-stage wall-clock seconds of the recorded steps.
  [[nodiscard]] const std::vector<double>& profile() const { return profile_; }

 private:
  void record_state(const BodyState& s);
  std::size_t n_;                      ///< bodies of the latest state (the file's n)
  int start_step_ = 0;                 ///< world.step_index() of state 0
  std::vector<std::size_t> state_size_;  ///< bodies of each recorded state (late bodies: inflow.hpp)
  std::vector<double> position_, angle_, velocity_, omega_, radius_, mass_;
  std::vector<std::int64_t> step_offset_;
  std::vector<std::int32_t> body_a_, body_b_, sweeps_, status_, feature_;
  ShapeTable shapes_;
  std::vector<double> point_, normal_, gap_, lambda_, theta_final_, residual_, profile_;
};

}  // namespace dc
