// The shape narrow phase's wall contacts (shape_narrow_phase.hpp): polygons placed at and around
// the reach of each wall give exactly the points collide_shape_plane finds for every body and
// wall (a box that skips a wall's test is one with no point there), and the contact list comes
// out strictly sorted by key.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "dc/engine/shape.hpp"
#include "dc/engine/shape_collide.hpp"
#include "dc/engine/shape_narrow_phase.hpp"
#include "dc/engine/world_def.hpp"

namespace dc {
namespace {

TEST(ShapeWallContacts, EveryPlanePointIsFoundAndTheListIsSorted) {
  WorldDef d;
  d.world.width = 30.0;
  d.world.height = 20.0;
  const ShapeDef box = make_box({1.0, 0.5}, "test"), tri = make_regular_polygon(3, 0.6, "test");
  std::mt19937_64 g(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  BodyState s;
  // Near each wall, turned at random: the nearest vertex from 0.36 m inside to 0.8 m away (the
  // reach: half the margin plus |v| Δt up to 2 cm).
  for (int k = 0; k < 400; ++k) {
    const double off = 0.2 + 0.6 * u(g), along = 2.0 + 16.0 * u(g);
    const Vec2 x = k % 4 == 0   ? Vec2{off, along}
                   : k % 4 == 1 ? Vec2{d.world.width - off, along}
                   : k % 4 == 2 ? Vec2{along, off}
                                : Vec2{along, d.world.height - off};
    const Vec2 v{3.0 * (u(g) - 0.5), 3.0 * (u(g) - 0.5)};
    s.add_shaped(k % 3 ? box : tri, Motion::Dynamic, x, 1.0, v, 6.3 * u(g));
  }
  ShapeNarrowPhase narrow;
  UniformGridBroadPhase grid;
  std::vector<Contact> contacts;
  narrow.collide(s, d, grid, contacts);
  for (std::size_t c = 1; c < contacts.size(); ++c) ASSERT_LT(contacts[c - 1].key, contacts[c].key) << c;

  // The same wall points found directly, in key order (walls top, bottom, right, left; bodies;
  // features ascending).
  struct Plane {
    Wall wall;
    Vec2 n;
    double offset;
  };
  const Plane planes[4] = {{Wall::Top, {0, -1}, -d.world.height},
                           {Wall::Bottom, {0, 1}, 0.0},
                           {Wall::Right, {-1, 0}, -d.world.width},
                           {Wall::Left, {1, 0}, 0.0}};
  std::vector<Vec2> wv, wn;
  std::vector<Contact> expected;
  for (const Plane& pl : planes)
    for (int k = 0; k < static_cast<int>(s.size()); ++k) {
      const ShapePose p = make_pose(s, k, wv, wn);
      ContactPoint pts[2];
      const double spec = shape_speculative_reach(s, k, d.contact, d.time.dt);
      const int m = collide_shape_plane(p, pl.n, pl.offset, 2 * spec, pts);
      if (m == 2 && pts[1].feature < pts[0].feature) std::swap(pts[0], pts[1]);
      for (int q = 0; q < m; ++q) {
        Contact c;
        c.key = ContactKey::wall(pl.wall, k, pts[q].feature);
        c.gap = pts[q].gap;
        c.point = pts[q].point;
        expected.push_back(c);
      }
    }
  size_t walls = 0;
  while (walls < contacts.size() && contacts[walls].key.is_wall()) ++walls;
  ASSERT_EQ(walls, expected.size());
  ASSERT_GT(walls, 100u);  // the placement reaches the walls
  for (size_t c = 0; c < walls; ++c) {
    EXPECT_EQ(contacts[c].key, expected[c].key) << c;
    EXPECT_EQ(contacts[c].gap, expected[c].gap) << c;
    EXPECT_EQ(contacts[c].point.x, expected[c].point.x) << c;
    EXPECT_EQ(contacts[c].point.y, expected[c].point.y) << c;
  }
}

}  // namespace
}  // namespace dc
