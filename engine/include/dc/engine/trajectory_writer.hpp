#pragma once
// Streams a simulation to its HDF5 trajectory file (`deepcontact simulate --out`; layout:
// docs/formats.md "Trajectory", the same datasets as TrajectoryRecorder writes) while it
// runs: every state, contact and solver figure is appended to OUT.tmp on disk as it is
// produced, through a buffer of at most a few MB, so memory does not grow with the number of
// steps (TrajectoryRecorder keeps everything in memory: bench frames, tests). commit() writes
// the body tables, closes the file, fsyncs it and renames it onto OUT; a writer destroyed
// without commit() removes OUT.tmp. A reader therefore sees the whole trajectory of the
// steps written or the earlier OUT, never a part.
//
// Bodies that enter during the run (inflow.hpp) widen the (state, body) datasets: their
// second axis is extendible, and the cells of states before a body existed read as NaN, as
// in the recorder's file.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dc/engine/world.hpp"

namespace dc {

class H5File;

class TrajectoryWriter {
 public:
  /// Creates OUT.tmp (replacing a stale one) and writes state 0 of `world`; `scene` is the
  /// TOML text of the scene. IoError naming the file when it cannot be created.
  TrajectoryWriter(std::string path, const World& world, const std::string& scene, const std::string& warmstart);
  /// Removes OUT.tmp unless committed.
  ~TrajectoryWriter();
  TrajectoryWriter(const TrajectoryWriter&) = delete;
  TrajectoryWriter& operator=(const TrajectoryWriter&) = delete;

  /// After world.step(): the step's contacts (with solved λ), solver figures, profile (the
  /// step's stages plus `record_seconds`, the caller's time spent recording the previous
  /// step) and the new state.
  void record_step(const World& world, const StepReport& report, double record_seconds);
  /// Writes the body tables of the latest state, flushes, closes, fsyncs and renames OUT.tmp
  /// onto OUT. IoError on failure (OUT unchanged, OUT.tmp removed).
  void commit();
  /// The same, renaming OUT.tmp onto `target` instead of OUT (an interrupted run's steps under
  /// a name that says so, leaving OUT as it was). `target` must be in OUT's file system.
  void commit(const std::string& target);

  [[nodiscard]] int steps() const { return steps_; }
  [[nodiscard]] std::int64_t contacts() const { return contacts_; }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  void buffer_state(const BodyState& s);
  void flush_buffers();

  std::string path_, tmp_;
  std::unique_ptr<H5File> file_;
  bool committed_ = false;
  int steps_ = 0;
  std::int64_t contacts_ = 0;
  std::size_t n_ = 0;  ///< bodies of the latest state (the file's n)
  std::vector<double> radius_, mass_;
  ShapeTable shapes_;
  // Buffered rows, written by flush_buffers(): states (all of width n_), contacts, per step.
  std::vector<double> position_, angle_, velocity_, omega_;
  std::vector<std::int64_t> step_offset_;
  std::vector<std::int32_t> body_a_, body_b_, feature_, sweeps_, status_;
  std::vector<double> point_, normal_, gap_, lambda_, theta_final_, residual_, profile_;
};

}  // namespace dc
