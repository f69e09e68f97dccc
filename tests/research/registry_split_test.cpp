// The registry a user's run draws from holds methods only: every starter of
// default_warm_starters() (and the cnn starters) reads nothing of this step's solution
// (uses_oracle() is false) and none is a negative control; add_research_starters() adds
// exactly the oracles and the controls, and all_warm_starters() is the union of the three.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "dc/research/research_starters.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {
namespace {

std::set<std::string> names_of(const WarmStarterRegistry& r) {
  const auto v = r.names();
  return {v.begin(), v.end()};
}

/// A spec that builds `name` (the starters that wrap another one need an inner starter).
std::string buildable(const std::string& name) {
  return name == "gate" || name == "gate-l2" ? name + ":builtin" : name;
}

TEST(RegistrySplit, TheDefaultRegistryHoldsOnlyMethods) {
  const WarmStarterRegistry r = default_warm_starters();
  ASSERT_FALSE(r.names().empty());
  for (const std::string& n : r.names()) {
    EXPECT_NE(n, "random");
    EXPECT_NE(n, "bad");
    EXPECT_FALSE(r.make(buildable(n))->uses_oracle()) << n << " reads this step's solution";
  }
}

TEST(RegistrySplit, TheResearchStartersAreExactlyTheOraclesAndControls) {
  WarmStarterRegistry research;
  add_research_starters(research);
  const std::set<std::string> names = names_of(research);
  EXPECT_EQ(names, (std::set<std::string>{"copy", "copy-noise", "copy-range", "copy-active", "copy-active-cg", "sph",
                                          "sph-residual", "sph-gain", "sph-gain-add", "random", "bad"}));
  for (const std::string& n : names) {
    const std::string spec = n == "copy-noise" ? "copy-noise:0.01" : n;
    const bool control = n == "random" || n == "bad";
    EXPECT_EQ(research.make(spec)->uses_oracle(), !control) << n;
  }
  // None of them is in the default registry.
  const std::set<std::string> methods = names_of(default_warm_starters());
  for (const std::string& n : names) EXPECT_FALSE(methods.count(n)) << n;
}

TEST(RegistrySplit, AllStartersAreMethodsCnnAndResearch) {
  const std::set<std::string> all = names_of(all_warm_starters("no-such-model.h5"));
  std::set<std::string> expected = names_of(default_warm_starters());
  WarmStarterRegistry research;
  add_research_starters(research);
  for (const auto& n : names_of(research)) expected.insert(n);
  expected.insert({"cnn", "cnn-hybrid"});
  EXPECT_EQ(all, expected);
}

}  // namespace
}  // namespace dc
