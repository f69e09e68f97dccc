// SphGrid: node counts, the documented (c, j = y row, i = x column) layout, bilinear
// interpolation (exact on linear fields, channels and axes not swapped), border clamping,
// validation.
#include <gtest/gtest.h>

#include <cmath>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/sph/sph_grid.hpp"

namespace dc {
namespace {

TEST(SphGrid, NodeCountsOfTheSeedSettings) {
  EXPECT_EQ(SphGrid(SphGridDef{30, 30, 0.5, 2}).nx(), 61);
  EXPECT_EQ(SphGrid(SphGridDef{30, 30, 0.5, 2}).ny(), 61);
  EXPECT_EQ(SphGrid(SphGridDef{30, 30, 0.25, 2}).nx(), 121);
  EXPECT_EQ(SphGrid(SphGridDef{30, 30, 1.0, 2}).nx(), 31);
  EXPECT_EQ(SphGrid(SphGridDef{30, 30, 0.1, 1}).nx(), 301);  // 30/0.1 = 299.99999999999994
  const SphGrid g(SphGridDef{30.2, 30, 0.5, 1});             // not a multiple: last node at 30
  EXPECT_EQ(g.nx(), 61);
  EXPECT_EQ(g.node(60, 0).x, 30.0);
}

TEST(SphGrid, LayoutIsChannelThenRowYThenColumnX) {
  const SphGrid g(SphGridDef{10.0, 4.0, 1.0, 3});  // nx = 11 (x), ny = 5 (y)
  ASSERT_EQ(g.nx(), 11);
  ASSERT_EQ(g.ny(), 5);
  EXPECT_EQ(g.size(), 3u * 5u * 11u);
  EXPECT_EQ(g.index(0, 0, 1), 1u);        // x is the fastest index
  EXPECT_EQ(g.index(0, 1, 0), 11u);       // next row = next y
  EXPECT_EQ(g.index(1, 0, 0), 55u);       // next channel
  EXPECT_EQ(g.index(2, 4, 10), 3u * 55u - 1u);
  EXPECT_EQ(g.node(3, 2).x, 3.0);         // node(i, j) = (i·d, j·d): j = 0 is y = 0 (bottom)
  EXPECT_EQ(g.node(3, 2).y, 2.0);
  EXPECT_EQ(g.channel(1).data(), g.data().data() + 55);
  EXPECT_EQ(g.channel(1).size(), 55u);
}

// Fills channel 0 with f0 = 2x + 3y + 1 and channel 1 with f1 = −x + 0.5y at the nodes.
SphGrid linear_fields(const SphGridDef& def) {
  SphGrid g(def);
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) {
      const Vec2 p = g.node(i, j);
      g.at(0, j, i) = 2 * p.x + 3 * p.y + 1;
      g.at(1, j, i) = -p.x + 0.5 * p.y;
    }
  return g;
}

TEST(SphGrid, BilinearIsExactOnLinearFieldsAndKeepsAxesAndChannels) {
  for (const double d : {1.0, 0.5, 0.25}) {
    const SphGrid g = linear_fields(SphGridDef{30, 20, d, 2});  // non-square on purpose
    Rng rng(7);
    for (int k = 0; k < 500; ++k) {
      const Vec2 p{rng.uniform(0, 30), rng.uniform(0, 20)};
      EXPECT_NEAR(g.bilinear(0, p), 2 * p.x + 3 * p.y + 1, 1e-11);
      EXPECT_NEAR(g.bilinear(1, p), -p.x + 0.5 * p.y, 1e-11);
    }
    EXPECT_EQ(g.bilinear(0, {3.0, 2.0}), 2 * 3.0 + 3 * 2.0 + 1);  // at a node: the node value
    EXPECT_EQ(g.bilinear(0, {30.0, 20.0}), 2 * 30.0 + 3 * 20.0 + 1);  // top-right corner
  }
}

TEST(SphGrid, BilinearClampsToTheBorder) {
  const SphGrid g = linear_fields(SphGridDef{30, 30, 0.5, 2});
  auto f0 = [](double x, double y) { return 2 * x + 3 * y + 1; };
  EXPECT_NEAR(g.bilinear(0, {-1.0, 5.2}), f0(0.0, 5.2), 1e-12);
  EXPECT_NEAR(g.bilinear(0, {31.0, 5.2}), f0(30.0, 5.2), 1e-12);
  EXPECT_NEAR(g.bilinear(0, {7.3, -0.01}), f0(7.3, 0.0), 1e-12);
  EXPECT_NEAR(g.bilinear(0, {40.0, 40.0}), f0(30.0, 30.0), 1e-12);
  EXPECT_NEAR(g.bilinear(0, {-1e300, 1e300}), f0(0.0, 30.0), 1e-12);
  // A box that is not a multiple of d: the node rectangle ends at x = 30 < W = 30.2.
  const SphGrid h = linear_fields(SphGridDef{30.2, 30, 0.5, 2});
  EXPECT_NEAR(h.bilinear(0, {30.1, 1.0}), f0(30.0, 1.0), 1e-12);
}

TEST(SphGrid, OneNodeAxisIsHandled) {
  SphGrid g(SphGridDef{0.3, 2.0, 0.5, 1});  // nx = 1
  ASSERT_EQ(g.nx(), 1);
  ASSERT_EQ(g.ny(), 5);
  for (int j = 0; j < g.ny(); ++j) g.at(0, j, 0) = j;
  EXPECT_NEAR(g.bilinear(0, {0.2, 0.75}), 1.5, 1e-12);
}

TEST(SphGrid, InvalidDefinitionsThrow) {
  auto make = [](double w, double h, double d, int c) { return SphGrid(SphGridDef{w, h, d, c}); };
  EXPECT_THROW(make(30, 30, 0.0, 1), InvalidArgument);
  EXPECT_THROW(make(30, 30, -0.5, 1), InvalidArgument);
  EXPECT_THROW(make(30, 30, std::nan(""), 1), InvalidArgument);
  EXPECT_THROW(make(30, 30, INFINITY, 1), InvalidArgument);
  EXPECT_THROW(make(0, 30, 0.5, 1), InvalidArgument);
  EXPECT_THROW(make(30, -1, 0.5, 1), InvalidArgument);
  EXPECT_THROW(make(std::nan(""), 30, 0.5, 1), InvalidArgument);
  EXPECT_THROW(make(INFINITY, 30, 0.5, 1), InvalidArgument);
  EXPECT_THROW(make(30, 30, 0.5, 0), InvalidArgument);
  EXPECT_THROW(make(30, 30, 0.5, -2), InvalidArgument);
  EXPECT_THROW(make(30, 30, 0.5, 5000), InvalidArgument);
  EXPECT_THROW(make(30, 30, 1e-3, 1), InvalidArgument);   // 30001 nodes per axis
  EXPECT_THROW(make(30, 30, 1e-300, 1), InvalidArgument); // W/d overflows int: still a clean error
  // The limit itself is accepted (validated without allocating 4096² values).
  EXPECT_NO_THROW((SphGridDef{4095.0, 1.0, 1.0, 1}.validate()));
  EXPECT_THROW((SphGridDef{4096.0, 1.0, 1.0, 1}.validate()), InvalidArgument);
  EXPECT_THROW((SphGridDef{1.0, 4096.0, 1.0, 1}.validate()), InvalidArgument);
  EXPECT_THROW((SphGridDef{4095.0, 4095.0, 1.0, 32}.validate()), InvalidArgument);  // > 2^28 values
}

}  // namespace
}  // namespace dc
