// `deepcontact render` end to end: a frame and an animation are written, bad
// input is one line and exit 1, and the paired bench report embeds a frame of its reference
// trajectory. (tests/python/test_render.py checks what is drawn against the trajectory.)
#include <gtest/gtest.h>

#include <filesystem>

#include "apps/cli_helpers.hpp"

namespace dc {
namespace {

std::string small_run(const test::TempDir& dir) {
  return "simulate --scene " + std::string(DC_SOURCE_DIR) + "/scenes/small.toml --steps 30 --out " + dir.file("run.h5");
}

TEST(RenderCli, WritesAFrameAndAGif) {
  test::TempDir dir;
  ASSERT_EQ(test::run_cli(small_run(dir)).exit_code, 0);
  auto r = test::run_cli("render " + dir.file("run.h5") + " --frame 20 --out " + dir.file("f.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(std::filesystem::file_size(dir.file("f.png")), 1000u);
  r = test::run_cli("render " + dir.file("run.h5") + " --every 10 --out " + dir.file("r.gif"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(std::filesystem::file_size(dir.file("r.gif")), 1000u);
}

TEST(RenderCli, BadInputIsOneLineAndExitOne) {
  test::TempDir dir;
  const auto r = test::run_cli("render " + dir.file("missing.h5") + " --out " + dir.file("r.gif"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("deepcontact: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("missing.h5"), std::string::npos) << r.err;
}

TEST(RenderCli, PairedBenchReportEmbedsAReferenceFrame) {
  test::TempDir dir;
  const auto r = test::run_cli("bench --scene " + std::string(DC_SOURCE_DIR) +
                               "/scenes/small.toml --steps 40 --seeds 1 --warmstarts zero,builtin --out " +
                               dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir.file("reference.h5")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("reference_frame.png"))) << test::slurp(dir.file("render.log"));
  EXPECT_NE(test::slurp(dir.file("report.md")).find("](reference_frame.png)"), std::string::npos);
}

}  // namespace
}  // namespace dc
