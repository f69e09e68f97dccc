// The data root is found relative to the running binary (no compiled-in source path), the
// environment override wins, and the build carries its commit.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <regex>

#include "dc/core/install_paths.hpp"

namespace dc {
namespace {

namespace fs = std::filesystem;

TEST(InstallPaths, TheBuildTreeHasADataRootNextToItsPrograms) {
  ::unsetenv("DEEPCONTACT_DATA_DIR");
  const fs::path root = data_root();
  EXPECT_TRUE(fs::exists(root / "models" / "default.h5")) << root;
  EXPECT_TRUE(fs::exists(data_path("bench/plots/render_trajectory.py"))) << root;
  // Found through the test binary's own directory (build/tests → build/share/deepcontact).
  EXPECT_EQ(fs::canonical(root / "models"), fs::canonical(fs::path(DC_SOURCE_DIR) / "models"));
}

TEST(InstallPaths, TheEnvironmentOverrides) {
  ::setenv("DEEPCONTACT_DATA_DIR", "/some/where", 1);
  EXPECT_EQ(data_root(), fs::path("/some/where"));
  EXPECT_EQ(data_path("models/default.h5"), fs::path("/some/where/models/default.h5"));
  ::unsetenv("DEEPCONTACT_DATA_DIR");
}

TEST(InstallPaths, CommitAndVersionAreWellFormed) {
  EXPECT_TRUE(std::regex_match(git_commit(), std::regex("[0-9a-f]{12}(-dirty)?|unknown"))) << git_commit();
  EXPECT_TRUE(std::regex_match(version(), std::regex("[0-9]+\\.[0-9]+\\.[0-9]+"))) << version();
}

}  // namespace
}  // namespace dc
