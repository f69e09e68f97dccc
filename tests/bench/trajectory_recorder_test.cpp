// dc::TrajectoryRecorder (dc_io): the written file holds the recorded states and contacts in
// the layout of docs/formats.md ("Trajectory"), read back through the same HDF5 layer.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "dc/engine/trajectory_recorder.hpp"
#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/io/h5.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

TEST(TrajectoryRecorder, FileHoldsTheRecordedStatesAndContacts) {
  WorldDef def;
  def.bodies.count = 10;
  World world(def);
  const auto solver = make_solver("pgs");
  SolverOptions opt;
  opt.max_sweeps = 50;
  TrajectoryRecorder rec(world);
  const BodyState first = world.bodies();
  const int steps = 80;
  for (int s = 0; s < steps; ++s) rec.record_step(world, world.step(*solver, opt));
  ASSERT_EQ(rec.steps(), steps);
  ASSERT_GT(rec.contacts(), 0u) << "the circles should reach the floor";

  const fs::path dir = fs::temp_directory_path() / "dc_trajectory_recorder_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "run.h5").string();
  rec.write(path, "scene text", "builtin");
  EXPECT_EQ(h5_open_object_count(), 0);

  const H5File f = H5File::open_read(path);
  const hsize_t n = first.size(), S = steps, C = rec.contacts();
  EXPECT_EQ(f.attribute_string("/", "format"), "deepcontact-trajectory");
  EXPECT_EQ(f.attribute_string("/", "scene"), "scene text");
  const auto pos = f.read<double>("/bodies/position", {S + 1, n, 2});
  for (hsize_t k = 0; k < n; ++k) {
    EXPECT_EQ(pos[2 * k], first.position[k].x);  // state 0 = before step 1
    EXPECT_EQ(pos[(S * n + k) * 2 + 1], world.bodies().position[k].y);  // state S = now
  }
  const auto offset = f.read<std::int64_t>("/contacts/step_offset", {S + 1});
  EXPECT_EQ(offset.front(), 0);
  EXPECT_EQ(static_cast<hsize_t>(offset.back()), C);
  const auto lambda = f.read<double>("/contacts/lambda", {C, 2});
  for (hsize_t c = 0; c < C; ++c) EXPECT_GE(lambda[2 * c], 0.0);
  f.require_shape("/solver/sweeps", {S});

  // A file that cannot be written is an IoError and leaves nothing behind.
  EXPECT_THROW(rec.write((dir / "missing" / "run.h5").string(), "", ""), IoError);
  EXPECT_FALSE(fs::exists(dir / "missing"));
  EXPECT_EQ(h5_open_object_count(), 1);  // only `f`
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dc
