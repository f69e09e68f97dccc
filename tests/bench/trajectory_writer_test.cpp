// dc::TrajectoryWriter: the streamed file equals the in-memory recorder's, dataset for
// dataset (bodies entering during the run included), OUT appears only at commit, and an
// uncommitted writer leaves neither OUT nor OUT.tmp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>

#include "dc/engine/trajectory_recorder.hpp"
#include "dc/engine/trajectory_writer.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/io/h5.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

struct Dir {
  fs::path path = fs::temp_directory_path() / ("dc_trajectory_writer_" + std::to_string(::getpid()));
  Dir() { fs::create_directories(path); }
  ~Dir() { fs::remove_all(path); }
  [[nodiscard]] std::string file(const char* name) const { return (path / name).string(); }
};

/// Every dataset of both files but the timings (/solver/profile) is bit-equal; NaN cells
/// (states before a body entered) compare equal as bit patterns.
void expect_same_trajectory(const std::string& a_path, const std::string& b_path) {
  const H5File a = H5File::open_read(a_path), b = H5File::open_read(b_path);
  for (const char* p : {"/bodies/position", "/bodies/angle", "/bodies/velocity", "/bodies/omega", "/bodies/radius",
                        "/bodies/mass", "/bodies/shape/semi_axes", "/bodies/shape/pivot", "/bodies/shape/vertices",
                        "/contacts/point", "/contacts/normal", "/contacts/gap", "/contacts/lambda",
                        "/solver/theta_final", "/solver/residual"}) {
    ASSERT_EQ(a.shape(p), b.shape(p)) << p;
    const auto x = a.read<double>(p), y = b.read<double>(p);
    ASSERT_EQ(x.size(), y.size()) << p;
    EXPECT_EQ(0, x.empty() ? 0 : std::memcmp(x.data(), y.data(), x.size() * sizeof(double))) << p;
  }
  for (const char* p : {"/contacts/body_a", "/contacts/body_b", "/contacts/feature", "/solver/sweeps", "/solver/status"})
    EXPECT_EQ(a.read<std::int32_t>(p), b.read<std::int32_t>(p)) << p;
  EXPECT_EQ(a.read<std::int64_t>("/contacts/step_offset"), b.read<std::int64_t>("/contacts/step_offset"));
  EXPECT_EQ(a.read<std::int64_t>("/bodies/shape/vertex_offset"), b.read<std::int64_t>("/bodies/shape/vertex_offset"));
  EXPECT_EQ(a.read<std::uint8_t>("/bodies/shape/kind"), b.read<std::uint8_t>("/bodies/shape/kind"));
  EXPECT_EQ(a.shape("/solver/profile"), b.shape("/solver/profile"));
  for (const char* attr : {"format", "scene", "warmstart"})
    EXPECT_EQ(a.attribute_string("/", attr), b.attribute_string("/", attr)) << attr;
}

void record_both(const WorldDef& def, int steps, const Dir& dir) {
  World world(def);
  const auto solver = make_solver("pgs");
  SolverOptions opt;
  opt.max_sweeps = 50;
  TrajectoryRecorder rec(world);
  TrajectoryWriter out(dir.file("streamed.h5"), world, "scene text", "builtin");
  for (int s = 0; s < steps; ++s) {
    const StepReport r = world.step(*solver, opt);
    rec.record_step(world, r);
    out.record_step(world, r, 0.0);
  }
  EXPECT_EQ(out.steps(), steps);
  EXPECT_EQ(static_cast<std::size_t>(out.contacts()), rec.contacts());
  EXPECT_FALSE(fs::exists(dir.file("streamed.h5"))) << "OUT must appear only at commit";
  EXPECT_TRUE(fs::exists(dir.file("streamed.h5.tmp")));
  out.commit();
  EXPECT_FALSE(fs::exists(dir.file("streamed.h5.tmp")));
  rec.write(dir.file("recorded.h5"), "scene text", "builtin");
  expect_same_trajectory(dir.file("recorded.h5"), dir.file("streamed.h5"));
}

TEST(TrajectoryWriter, StreamedFileEqualsTheRecordersFile) {
  const Dir dir;
  WorldDef def;
  def.bodies.count = 10;
  record_both(def, 80, dir);
  ASSERT_GT(H5File::open_read(dir.file("streamed.h5")).shape("/contacts/gap")[0], 0u) << "the circles reach the floor";
}

TEST(TrajectoryWriter, BodiesEnteringDuringTheRunWidenTheStatesWithNaN) {
  const Dir dir;
  const WorldDef def = load_scene(std::string(DC_SOURCE_DIR) + "/scenes/pour.toml");
  record_both(def, 30, dir);
  const H5File f = H5File::open_read(dir.file("streamed.h5"));
  const auto n = f.shape("/bodies/angle")[1];
  const auto first = f.read_rows<double>("/bodies/angle", 0, 1);
  ASSERT_GT(n, 1u);
  EXPECT_TRUE(std::isnan(first[n - 1])) << "the last body entered after state 0";
}

TEST(TrajectoryWriter, UncommittedWriterLeavesNothing) {
  const Dir dir;
  {
    WorldDef def;
    def.bodies.count = 5;
    const World world(def);
    TrajectoryWriter out(dir.file("never.h5"), world, "", "");
  }
  EXPECT_FALSE(fs::exists(dir.file("never.h5")));
  EXPECT_FALSE(fs::exists(dir.file("never.h5.tmp")));
  EXPECT_EQ(h5_open_object_count(), 0);
}

}  // namespace
}  // namespace dc
