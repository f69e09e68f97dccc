// The family tools of the bench (docs/bench.md): the higher cap (--max-sweeps) agrees with the
// fixed-cap run where that converged and only adds sweeps where it did not; the warm-up
// skips steps; --no-oracle refuses oracle starters; scale_scene keeps the shape.
#include <gtest/gtest.h>

#include <cmath>

#include "bench/bench_fixtures.hpp"
#include "dc/bench/bench_runner.hpp"
#include "dc/bench/bench_summary.hpp"
#include "dc/bench/scale_sweep.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"

namespace dc {
namespace {

using test::capped_pile;
using test::get;
using test::small_pile;


TEST(FamiliesBench, HigherCapExtendsOnlyTheUnconvergedSteps) {
  const auto r = bench::run_bench(capped_pile(), default_warm_starters());
  int extended = 0;
  for (const auto& rec : r.starters) {
    ASSERT_EQ(rec.sweeps_to_tol_high.size(), rec.sweeps_to_tol.size());
    for (std::size_t k = 0; k < rec.sweeps_to_tol.size(); ++k) {
      if (rec.sweeps_to_tol[k] >= 0) {
        EXPECT_EQ(rec.sweeps_to_tol_high[k], rec.sweeps_to_tol[k]);
      } else if (rec.sweeps_to_tol_high[k] >= 0) {
        EXPECT_GT(rec.sweeps_to_tol_high[k], 60);
        EXPECT_LE(rec.sweeps_to_tol_high[k], 2000);
        ++extended;
      }
    }
  }
  EXPECT_GT(extended, 0);
  for (const auto& s : bench::summarise(r)) {
    EXPECT_LE(s.unconverged_share_high, s.unconverged_share) << s.name;
    EXPECT_GE(s.median_sweeps_high, std::min(s.median_sweeps_to_tol, 61.0)) << s.name;
    EXPECT_TRUE(std::isfinite(s.residual_at_budget)) << s.name;
    EXPECT_TRUE(std::isfinite(s.residual_at_cap)) << s.name;
  }
}

TEST(ScaleScene, KeepsAspectRatioAndFillingOrTheWidth) {
  WorldDef d = load_scene(std::string(DC_SOURCE_DIR) + "/scenes/deep.toml");
  ASSERT_EQ(bench::scene_body_count(d), 1000);
  const WorldDef q = bench::scale_scene(d, 250, bench::ScaleAxis::Both);
  EXPECT_EQ(q.bodies.count, 250);
  EXPECT_NEAR(q.world.width / q.world.height, d.world.width / d.world.height, 1e-12);
  EXPECT_NEAR(q.world.width * q.world.height, d.world.width * d.world.height / 4, 1e-9);  // same filling
  EXPECT_NEAR(q.bodies.region[3], d.bodies.region[3] / 2, 1e-12);
  EXPECT_EQ(q.bodies.radius, d.bodies.radius);
  const WorldDef h = bench::scale_scene(d, 250, bench::ScaleAxis::Height);
  EXPECT_EQ(h.world.width, d.world.width);
  EXPECT_NEAR(h.world.height, d.world.height / 4, 1e-12);
  // The pour family scales its inflow rate (its bodies are all poured).
  const WorldDef p = load_scene(std::string(DC_SOURCE_DIR) + "/scenes/pour.toml");
  EXPECT_EQ(bench::scene_body_count(p), 450);
  EXPECT_NEAR(bench::scale_scene(p, 900, bench::ScaleAxis::Both).inflow.rate, 2 * p.inflow.rate, 1e-9);
  EXPECT_THROW(bench::scale_scene(d, 0, bench::ScaleAxis::Both), ConfigError);
}

// scenes/impact_1000.toml is impact.toml as the size sweep scales it to 1,000 bodies (sides
// rounded to whole metres), with the same heavy disc, and its 1,000 circles can be placed
// (impact.toml's 20 m box cannot hold them).
TEST(ScaleScene, ImpactAtThousandBodiesIsTheScaledImpactScene) {
  const WorldDef base = load_scene(std::string(DC_SOURCE_DIR) + "/scenes/impact.toml");
  const WorldDef big = load_scene(std::string(DC_SOURCE_DIR) + "/scenes/impact_1000.toml");
  EXPECT_EQ(bench::scene_body_count(big), 1001);
  const WorldDef scaled = bench::scale_scene(base, 1001, bench::ScaleAxis::Both);
  EXPECT_NEAR(big.world.width, scaled.world.width, 0.5);
  EXPECT_NEAR(big.world.height, scaled.world.height, 0.5);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(big.bodies.region[k], scaled.bodies.region[k], 0.5) << k;
  EXPECT_EQ(big.bodies.radius, base.bodies.radius);
  ASSERT_EQ(big.body.size(), 1u);
  EXPECT_NEAR(big.body[0].position.x, scaled.body[0].position.x, 0.5);
  EXPECT_NEAR(big.body[0].position.y, scaled.body[0].position.y, 0.5);
  EXPECT_EQ(big.body[0].radius, base.body[0].radius);
  EXPECT_EQ(big.body[0].density, base.body[0].density);
  EXPECT_EQ(big.body[0].spawn, base.body[0].spawn);
  EXPECT_TRUE(big.body[0].velocity == base.body[0].velocity);
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {  // the family's evaluation seeds
    WorldDef d = big;
    d.bodies.seed = seed;
    EXPECT_EQ(World(d).bodies().size(), 1000u) << "seed " << seed;  // the disc enters at t = 2 s
  }
}

}  // namespace
}  // namespace dc
