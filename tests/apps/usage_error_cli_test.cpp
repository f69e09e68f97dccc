// One-line errors and right labels of the executable, each a case a new user hit: CLI11's
// parse errors rewritten (closest option, readable range, exit status 2), render checking
// its output before drawing, `lcp solve` on a directory, and `simulate`'s body count by shape.
#include <gtest/gtest.h>

#include <filesystem>

#include "apps/cli_helpers.hpp"
#include "commands/usage_error.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

void expect_one_line_error(const test::CliResult& r, int status, const std::string& needle) {
  EXPECT_EQ(r.exit_code, status) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("deepcontact: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
  EXPECT_LT(r.err.size(), 200u) << r.err;  // no 309-digit bound, no usage dump
}

TEST(UsageErrors, AMisspelledOptionSuggestsTheClosestAndExitsTwo) {
  const auto r = test::run_cli("simulate --stpes 3");
  expect_one_line_error(r, 2, "did you mean --steps?");
}

TEST(UsageErrors, AMisspelledSubcommandSuggestsTheClosest) {
  const auto r = test::run_cli("simulat --steps 3");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("simulate"), std::string::npos) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
}

TEST(UsageErrors, ANegativeCountSaysTheBoundReadably) {
  const auto r = test::run_cli("simulate --steps -3");
  expect_one_line_error(r, 2, "--steps");
  EXPECT_NE(r.err.find("must be >= 0"), std::string::npos) << r.err;
}

TEST(UsageErrors, HelpAndVersionStillSucceed) {
  EXPECT_EQ(test::run_cli("simulate --help").exit_code, 0);
  const auto v = test::run_cli("--version");
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find("commit "), std::string::npos) << v.out;  // the build's git commit
}

TEST(UsageErrors, ClosestNameNeedsACloseCandidate) {
  EXPECT_EQ(cli::closest_name("--stpes", {"--steps", "--scene", "--set"}), "--steps");
  EXPECT_EQ(cli::closest_name("--warmstrat", {"--warmstart", "--out"}), "--warmstart");
  EXPECT_EQ(cli::closest_name("--zzzzzz", {"--steps", "--out"}), "");
}

TEST(InputErrors, LcpSolveOnADirectorySaysSo) {
  test::TempDir dir;
  const auto r = test::run_cli("lcp solve " + dir.path().string());
  expect_one_line_error(r, 1, "is a directory");
}

class RenderOutput : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto r = test::run_cli("simulate --scene " + std::string(DC_SOURCE_DIR) + "/scenes/small.toml --steps 5 --out " +
                                 dir.file("run.h5"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  test::TempDir dir;
};

TEST_F(RenderOutput, AFrameWithAWrongExtensionIsOneLine) {
  const auto r = test::run_cli("render " + dir.file("run.h5") + " --out " + dir.file("y.txt") + " --frame 1");
  expect_one_line_error(r, 1, ".png");
  EXPECT_FALSE(fs::exists(dir.file("y.txt")));
}

TEST_F(RenderOutput, ADirectoryAsOutputIsRefusedAndNothingIsWritten) {
  fs::create_directory(dir.file("adir"));
  const auto r = test::run_cli("render " + dir.file("run.h5") + " --out " + dir.file("adir") + " --frame 1");
  expect_one_line_error(r, 1, "is a directory");
  EXPECT_FALSE(fs::exists(dir.file("adir.png")));
  EXPECT_TRUE(fs::is_empty(dir.file("adir")));
}

TEST(Labels, SimulateCountsBodiesByShape) {
  const std::string scenes = std::string(DC_SOURCE_DIR) + "/scenes/";
  const auto boxes = test::run_cli("simulate --scene " + scenes + "box_pile.toml --steps 2");
  ASSERT_EQ(boxes.exit_code, 0) << boxes.err;
  EXPECT_EQ(boxes.out.find(" circles for "), std::string::npos) << boxes.out;
  EXPECT_NE(boxes.out.find("polygons for "), std::string::npos) << boxes.out;
  const auto mixed = test::run_cli("simulate --scene " + scenes + "mixed.toml --steps 2");
  ASSERT_EQ(mixed.exit_code, 0) << mixed.err;
  EXPECT_NE(mixed.out.find(" bodies ("), std::string::npos) << mixed.out;  // "66 bodies (6 circles, …)"
  const auto seed = test::run_cli("simulate --steps 2");
  EXPECT_NE(seed.out.find("Simulated 100 circles for "), std::string::npos) << seed.out;
}

}  // namespace
}  // namespace dc

namespace dc {
namespace {

TEST(UsageErrors, AValueThatIsNoNumberSaysSo) {
  const auto r = test::run_cli("simulate --steps abc");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--steps: 'abc' is not an integer"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("out of range"), std::string::npos) << r.err;
  const auto f = test::run_cli("lcp solve x.dat --tol abc");
  EXPECT_NE(f.err.find("--tol: 'abc' is not a number"), std::string::npos) << f.err;
  const auto big = test::run_cli("simulate --steps 99999999999");
  EXPECT_NE(big.err.find("--steps: 99999999999 is out of range"), std::string::npos) << big.err;
}

TEST(UsageErrors, AnExactIntegerInScientificNotationIsTaken) {
  const auto r = test::run_cli("simulate --steps 1e1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(" for 10 steps"), std::string::npos) << r.out;
  const auto frac = test::run_cli("simulate --steps 2.5");
  EXPECT_EQ(frac.exit_code, 2);
  EXPECT_NE(frac.err.find("--steps: 2.5 is not an integer"), std::string::npos) << frac.err;
}

TEST(UsageErrors, AMisspelledInnerSubcommandSuggestsTheClosest) {
  const auto r = test::run_cli("lcp solv f.dat");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("unknown subcommand 'solv'; did you mean 'solve'?"), std::string::npos) << r.err;
  const auto none = test::run_cli("lcp");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("deepcontact lcp needs a subcommand: solve or convert"), std::string::npos) << none.err;
  const auto top = test::run_cli("simulat --steps 3");
  EXPECT_NE(top.err.find("unknown subcommand 'simulat'; did you mean 'simulate'?"), std::string::npos) << top.err;
}

}  // namespace
}  // namespace dc
