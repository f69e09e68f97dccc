// Bad values refused at the door, and the shipped model in ordinary runs at any sweep count
// (docs/robustness.md "Bad values refused at the door", docs/learning.md "Bounded guesses").
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "apps/cli_helpers.hpp"

namespace dc {
namespace {

TEST(BadValuesCli, SceneValuesThatOverflowOrCannotFitAreOneLineErrors) {
  struct Case {
    const char* set;
    const char* says;
  };
  for (const Case& c : {Case{"--set bodies.density=1e308", "mass [kg] = inf overflows"},
                        Case{"--set bodies.count=10000000 --set world.width=20000 --set world.height=20000",
                             "more than the limit of 1000000"},
                        Case{"--set bodies.count=2000", "densest packing"},
                        Case{"--set inflow.velocity=[nan,0.0]", "expected a finite number"}}) {
    SCOPED_TRACE(c.set);
    const auto r = test::run_cli(std::string("simulate --steps 50 ") + c.set);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(test::count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

/// Total energy at the start and at the end from `simulate`'s summary line.
std::pair<double, double> energies(const std::string& out) {
  const auto at = out.find("total energy ");
  if (at == std::string::npos) return {0.0, 0.0};
  char* end = nullptr;
  const double e0 = std::strtod(out.c_str() + at + 13, &end);
  const auto arrow = out.find("-> ", at);
  return {e0, arrow == std::string::npos ? 0.0 : std::strtod(out.c_str() + arrow + 3, nullptr)};
}

// The seed pile settles under gravity and friction: whatever the sweep count, no warm start may
// add energy. With the shipped model, 5 sweeps once exited 1 ("sph transfer: value of point
// 1429, channel 2 is not finite") and 1, 2 or 4 sweeps ended at 1e17 J and more.
TEST(BadValuesCli, TheShippedModelRunsAtAnySweepCount) {
  for (const int sweeps : {1, 2, 5}) {
    SCOPED_TRACE(sweeps);
    const auto r = test::run_cli("simulate --steps 300 --set solver.sweeps=" + std::to_string(sweeps) +
                                 " --warmstart cnn:" + std::string(DC_SOURCE_DIR) + "/models/default.h5");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto [e0, e1] = energies(r.out);
    EXPECT_GT(e0, 0.0) << r.out;
    EXPECT_LT(e1, e0) << r.out;
  }
}

}  // namespace
}  // namespace dc
