// The report's `theses` column (the earlier theses' iterations on the seed scene) is shown
// only for the seed scene: on another family it would label that family with figures
// measured elsewhere.
#include <gtest/gtest.h>

#include "dc/bench/bench_report.hpp"
#include "dc/engine/scene.hpp"

namespace dc {
namespace {

TEST(ThesesColumn, AppliesToTheSeedSceneWithAnySeedAndLength) {
  WorldDef seed;
  EXPECT_TRUE(bench::theses_apply(seed));
  seed.bodies.seed = 7;
  seed.time.steps = 40;
  EXPECT_TRUE(bench::theses_apply(seed));
  EXPECT_TRUE(bench::theses_apply(load_scene(std::string(DC_SOURCE_DIR) + "/scenes/seed.toml")));
}

TEST(ThesesColumn, DoesNotApplyToOtherFamilies) {
  for (const char* scene : {"box_pile.toml", "deep.toml", "small.toml", "mixed.toml"})
    EXPECT_FALSE(bench::theses_apply(load_scene(std::string(DC_SOURCE_DIR) + "/scenes/" + scene))) << scene;
  WorldDef more;
  more.bodies.count = 120;
  EXPECT_FALSE(bench::theses_apply(more));
}

TEST(ThesesColumn, TheTableHasTheColumnOnlyForTheSeedScene) {
  bench::BenchResults r;
  r.options.sweeps = 100;
  bench::StarterSummary builtin;
  builtin.name = "builtin";
  EXPECT_NE(bench::format_table(r, {builtin}, true).find("theses"), std::string::npos);
  EXPECT_NE(bench::format_table(r, {builtin}, true).find("230-245"), std::string::npos);
  r.options.scene = load_scene(std::string(DC_SOURCE_DIR) + "/scenes/box_pile.toml");
  EXPECT_EQ(bench::format_table(r, {builtin}, true).find("theses"), std::string::npos);
  EXPECT_EQ(bench::format_table(r, {builtin}, true).find("230-245"), std::string::npos);
}

}  // namespace
}  // namespace dc
