// deepcontact simulate: the trajectory file holds what docs/formats.md promises, and bad
// input gives a one-line error with a non-zero exit status.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include "cli_helpers.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/io/h5.hpp"

namespace dc {
namespace {

TEST(SimulateCli, WritesTheDocumentedTrajectory) {
  test::TempDir dir;
  const std::string out = dir.file("run.h5");
  const auto r = test::run_cli("simulate --set bodies.count=12 --set bodies.mean=[15.0,4.0] --set bodies.sigma=3.0 "
                               "--set solver.sweeps=300 --steps 60 --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Simulated 12 circles for 60 steps"), std::string::npos) << r.out;
  const H5File f = H5File::open_read(out);
  f.require_shape("/bodies/position", {61, 12, 2});
  f.require_shape("/bodies/velocity", {61, 12, 2});
  f.require_shape("/bodies/angle", {61, 12});
  f.require_shape("/bodies/omega", {61, 12});
  f.require_shape("/bodies/radius", {12});
  f.require_shape("/bodies/mass", {12});
  f.require_shape("/solver/sweeps", {60});
  f.require_shape("/solver/theta_final", {60});
  f.require_shape("/solver/residual", {60});
  const auto off = f.read<std::int64_t>("/contacts/step_offset", {61});
  EXPECT_EQ(off.front(), 0);
  for (std::size_t k = 1; k < off.size(); ++k) EXPECT_GE(off[k], off[k - 1]);
  const auto C = static_cast<hsize_t>(off.back());
  ASSERT_GT(C, 0u) << "the bodies should reach the floor within 60 steps";
  f.require_shape("/contacts/body_a", {C});
  f.require_shape("/contacts/body_b", {C});
  f.require_shape("/contacts/point", {C, 2});
  f.require_shape("/contacts/normal", {C, 2});
  f.require_shape("/contacts/gap", {C});
  f.require_shape("/contacts/lambda", {C, 2});
  const auto a = f.read<std::int32_t>("/contacts/body_a");
  const auto b = f.read<std::int32_t>("/contacts/body_b");
  bool saw_floor = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_GE(a[i], -4);
    EXPECT_LT(a[i], 12);
    EXPECT_GE(b[i], 0);
    EXPECT_LT(b[i], 12);
    if (a[i] >= 0) {
      EXPECT_LT(a[i], b[i]);
    }
    saw_floor |= a[i] == -3;  // bottom wall
  }
  EXPECT_TRUE(saw_floor);
  const auto lam = f.read<double>("/contacts/lambda");
  for (std::size_t i = 0; i < C; ++i) EXPECT_GE(lam[2 * i], 0.0);
  // The scene attribute is the complete scene and parses back to what ran.
  const WorldDef d = parse_scene(f.attribute_string("/", "scene"));
  EXPECT_EQ(d.bodies.count, 12);
  EXPECT_EQ(d.solver.sweeps, 300);
  EXPECT_EQ(d.time.steps, 60);
}

// --hash prints state_hash of the final state, which is the last state of the written
// trajectory read back bit for bit, and two runs of the same scene print the same hash.
TEST(SimulateCli, HashIsThatOfTheLastTrajectoryStateAndRepeats) {
  test::TempDir dir;
  const std::string out = dir.file("run.h5");
  const std::string scene =
      "simulate --set bodies.count=12 --set bodies.mean=[15.0,4.0] --set bodies.sigma=3.0 --set solver.sweeps=300 "
      "--steps 60 ";
  const auto r = test::run_cli(scene + "--hash --out " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(r.out.size(), 17u) << r.out;  // 16 hex digits and a newline, nothing else
  const std::uint64_t printed = std::stoull(r.out, nullptr, 16);

  const H5File f = H5File::open_read(out);
  const auto pos = f.read_rows<double>("/bodies/position", 60, 1);
  const auto vel = f.read_rows<double>("/bodies/velocity", 60, 1);
  const auto ang = f.read_rows<double>("/bodies/angle", 60, 1);
  const auto om = f.read_rows<double>("/bodies/omega", 60, 1);
  ASSERT_EQ(pos.size(), 24u);
  BodyState last;
  for (std::size_t k = 0; k < 12; ++k) {
    last.position.push_back({pos[2 * k], pos[2 * k + 1]});
    last.velocity.push_back({vel[2 * k], vel[2 * k + 1]});
    last.angle.push_back(ang[k]);
    last.omega.push_back(om[k]);
  }
  EXPECT_EQ(state_hash(last), printed);
  // The state moved: the first state's hash differs from the last one's.
  BodyState first = last;
  const auto pos0 = f.read_rows<double>("/bodies/position", 0, 1);
  for (std::size_t k = 0; k < 12; ++k) first.position[k] = {pos0[2 * k], pos0[2 * k + 1]};
  EXPECT_NE(state_hash(first), printed);

  const auto again = test::run_cli(scene + "--hash");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out, r.out);
  // The summary line carries the same hash.
  const auto summary = test::run_cli(scene);
  ASSERT_EQ(summary.exit_code, 0) << summary.err;
  EXPECT_NE(summary.out.find("final state hash " + r.out.substr(0, 16)), std::string::npos) << summary.out;
}

TEST(SimulateCli, BadInputIsOneLineAndNonZero) {
  test::TempDir dir;
  for (const std::string& args : std::vector<std::string>{"--set contact.frictoin=0.3", "--set time.dt=nan", "--set bodies.radius=-1",
                                 "--scene " + dir.file("missing.toml"), "--set bodies.count=x"}) {
    const auto r = test::run_cli("simulate --steps 1 " + args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(test::count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
  }
  const auto r = test::run_cli("simulate --steps 1 --set contact.frictoin=0.3");
  EXPECT_NE(r.err.find("frictoin"), std::string::npos) << r.err;
}

// SIGTERM (a batch system's time limit) stops simulate at the next step: the trajectory of
// the steps done is committed under OUT-STEM.interrupted.h5 (complete, readable; OUT itself is
// not written), one line says so, exit 143.
TEST(SimulateCli, SigtermCommitsTheStepsDoneAndExits143) {
  test::TempDir dir;
  const std::string out = dir.file("run.h5"), err = dir.file("err.txt");
  const pid_t pid = test::spawn_cli("simulate --set bodies.count=12 --set bodies.mean=[15.0,4.0] --set "
                                    "bodies.sigma=3.0 --steps 1000000 --out " + out,
                                    err, test::ChildLog::StderrOnly);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(test::wait_for_file(out + ".tmp", pid));
  ::usleep(300000);
  ::kill(pid, SIGTERM);
  ASSERT_EQ(test::wait_exit(pid), 143) << test::slurp(err);
  const std::string log = test::slurp(err);
  EXPECT_NE(log.find("interrupted by SIGTERM after "), std::string::npos) << log;
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
  EXPECT_FALSE(std::filesystem::exists(out));
  const H5File f = H5File::open_read(dir.file("run.interrupted.h5"));
  const auto S = f.shape("/solver/sweeps").at(0);
  EXPECT_GT(S, 0u);
  EXPECT_LT(S, 1000000u);
  f.require_shape("/bodies/position", {S + 1, 12, 2});
  EXPECT_EQ(f.read<std::int64_t>("/contacts/step_offset").size(), S + 1);
  EXPECT_FALSE(std::filesystem::exists(out + ".tmp"));
}

}  // namespace
}  // namespace dc
