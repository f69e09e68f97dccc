// Scene values refused at the door for what they imply (docs/robustness.md "Bad values refused
// at the door"): masses, inertias and energies that overflow or whose inverses would, more
// bodies than fit where they are placed or than the stated limit, and NaN/inf in every key —
// also the keys a scene does not use — each a one-line ConfigError naming the key.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"

namespace dc {
namespace {

std::string refusal(const std::vector<std::string>& sets) {
  WorldDef d;
  try {
    for (const auto& s : sets) apply_override(d, s);
    d.validate();
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a ConfigError for " << sets.front();
  return {};
}

#define EXPECT_CONTAINS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << "message: " << (haystack)

TEST(SceneLimits, DerivedQuantitiesThatOverflowAreRefused) {
  // ρ = 1e308 kg/m²: m = ρπr² = inf; the world would run with -nan energy.
  EXPECT_CONTAINS(refusal({"bodies.density=1e308"}), "[bodies]: mass [kg] = inf overflows");
  // Finite mass, but the energy scale m |g| (W + H) overflows.
  EXPECT_CONTAINS(refusal({"bodies.density=1e150"}), "[bodies]: mass [kg]");
  EXPECT_CONTAINS(refusal({"bodies.density=1e-300"}), "is too small");
  EXPECT_CONTAINS(refusal({"world.gravity=[0.0, -1e300]"}), "energy scale");
  const auto body_refusal = [](const std::string& keys) {
    try {
      (void)parse_scene("[bodies]\ncount = 0\n[[body]]\nposition = [5.0, 5.0]\n" + keys, "scene.toml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << "expected a ConfigError for " << keys;
    return std::string();
  };
  EXPECT_CONTAINS(body_refusal("velocity = [1e200, 0.0]\n"), "[[body]] #1: energy scale");
  EXPECT_CONTAINS(body_refusal("density = 1e308\n"), "[[body]] #1: mass");
  EXPECT_CONTAINS(refusal({"inflow.region=[1.0,1.0,2.0,2.0]", "inflow.stop=1", "inflow.density=1e308",
                           "inflow.rate=1"}),
                  "[inflow]: mass");
  // Every accepted density gives a finite world: the largest one accepted still steps.
  WorldDef ok;
  apply_override(ok, "bodies.density=1e90");
  apply_override(ok, "bodies.count=5");
  ok.validate();
  World w(ok);
  EXPECT_TRUE(std::isfinite(w.kinetic_energy() + w.potential_energy()));
}

/// The ConfigError of making the world's bodies (World's constructor) with `sets` applied.
std::string world_refusal(const std::vector<std::string>& sets) {
  WorldDef d;
  for (const auto& s : sets) apply_override(d, s);
  try {
    World w(d);
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a ConfigError for " << sets.front();
  return {};
}

TEST(SceneLimits, BodiesThatCannotFitAreRefusedBeforeAnyIsPlaced) {
  // Ten million circles in a 20 km box: the stated limit, said before any placement (before:
  // minutes of placement at 4 GB).
  EXPECT_CONTAINS(world_refusal({"world.width=20000", "world.height=20000", "bodies.region=[0.0,0.0,20000.0,20000.0]",
                                 "bodies.count=10000000"}),
                  "[bodies] count: 10000000 bodies is more than the limit of 1000000");
  // More circle area than the densest packing of the box (or region, or the Gaussian's reach).
  EXPECT_CONTAINS(world_refusal({"bodies.count=400"}), "more than the densest packing");
  EXPECT_CONTAINS(world_refusal({"bodies.region=[1.0,1.0,5.0,5.0]", "bodies.count=50"}), "densest packing");
  EXPECT_CONTAINS(world_refusal({"bodies.sigma=0.1", "bodies.count=20"}), "densest packing");
  // The seed scene and a dense but feasible pile are made.
  EXPECT_EQ(World(WorldDef{}).bodies().size(), 100u);
  WorldDef d;
  apply_override(d, "bodies.region=[1.0,1.0,29.0,29.0]");
  apply_override(d, "bodies.count=120");
  EXPECT_EQ(World(d).bodies().size(), 120u);
}

TEST(SceneLimits, NanAndInfAreRefusedInEveryKeyEvenUnusedOnes) {
  for (const char* set : {"bodies.size=[nan, 1.0]", "bodies.semi_axes=[1.0, inf]", "inflow.velocity=[nan, 0.0]",
                          "inflow.region=[0.0, 0.0, inf, 1.0]", "inflow.density=nan", "inflow.radius=inf"}) {
    SCOPED_TRACE(set);
    const std::string m = refusal({set});
    EXPECT_CONTAINS(m, "expected a finite number");
    EXPECT_EQ(m.find('\n'), std::string::npos);
  }
}

}  // namespace
}  // namespace dc
