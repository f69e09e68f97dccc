// [bodies] order = "morton": the generated bodies numbered by the Morton code of their initial
// cell (world/spatial_order.hpp). The same bodies as the creation order, renumbered; reruns
// bit-equal; the physics the same up to the Gauss–Seidel row order (agreement to rounding of
// the converged solve, not bit equality).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <tuple>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "world/spatial_order.hpp"

namespace dc {
namespace {

/// The scaled seed pile with its generated bodies numbered in `order`.
WorldDef pile(BodyOrder order, int n) {
  WorldDef d = stress::scaled_seed_pile(n);
  d.bodies.order = order;
  return d;
}

TEST(MortonOrder, CodeInterleavesXInEvenAndYInOddBits) {
  EXPECT_EQ(morton_code(0, 0), 0u);
  EXPECT_EQ(morton_code(1, 0), 1u);
  EXPECT_EQ(morton_code(0, 1), 2u);
  EXPECT_EQ(morton_code(3, 3), 15u);
  EXPECT_EQ(morton_code(4, 0), 16u);
  EXPECT_EQ(morton_code(0xffffffffu, 0), 0x5555555555555555ULL);  // every even bit
  EXPECT_EQ(morton_code(0, 0xffffffffu), 0xaaaaaaaaaaaaaaaaULL);  // every odd bit
}

TEST(MortonOrder, IsAPermutationWithNonDecreasingCodes) {
  std::vector<Vec2> x;
  for (int k = 0; k < 500; ++k) x.push_back({std::fmod(k * 7.31, 40.0) - 3.0, std::fmod(k * 3.17, 25.0) + 1.0});
  const double cell = 2.0;
  const std::vector<int> order = morton_order(x, cell);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> ids(x.size());
  std::iota(ids.begin(), ids.end(), 0);
  EXPECT_EQ(sorted, ids);
  double x0 = 1e300, y0 = 1e300;
  for (const Vec2 p : x) x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
  auto code = [&](int k) {
    const Vec2 p = x[static_cast<size_t>(k)];
    return morton_code(static_cast<std::uint32_t>(std::floor((p.x - x0) / cell)),
                       static_cast<std::uint32_t>(std::floor((p.y - y0) / cell)));
  };
  for (std::size_t i = 1; i < order.size(); ++i) {
    ASSERT_LE(code(order[i - 1]), code(order[i])) << "at " << i;
    if (code(order[i - 1]) == code(order[i])) {
      EXPECT_LT(order[i - 1], order[i]) << "ties in index order";
    }
  }
  EXPECT_THROW((void)morton_order(x, 0.0), InvalidArgument);
}

TEST(BodyOrder, MortonNumbersTheSameBodiesCloserInSpace) {
  const World a(pile(BodyOrder::Creation, 400)), b(pile(BodyOrder::Morton, 400));
  auto sorted = [](const BodyState& s) {
    std::vector<std::tuple<double, double, double>> v;
    for (std::size_t k = 0; k < s.size(); ++k) v.emplace_back(s.position[k].x, s.position[k].y, s.radius[k]);
    std::sort(v.begin(), v.end());
    return v;
  };
  ASSERT_EQ(a.bodies().size(), b.bodies().size());
  EXPECT_EQ(sorted(a.bodies()), sorted(b.bodies()));
  // Locality: consecutive indices are on average much closer in space.
  auto mean_step = [](const BodyState& s) {
    double sum = 0;
    for (std::size_t k = 1; k < s.size(); ++k) sum += length(s.position[k] - s.position[k - 1]);
    return sum / static_cast<double>(s.size() - 1);
  };
  EXPECT_LT(mean_step(b.bodies()), 0.5 * mean_step(a.bodies()));
}

TEST(BodyOrder, ExplicitBodiesFollowInFileOrder) {
  WorldDef d = pile(BodyOrder::Morton, 50);
  BodyDef e1, e2;
  e1.position = {2.0, 19.0};
  e2.position = {19.0, 19.0};
  d.body = {e1, e2};
  const World w(d);
  ASSERT_EQ(w.bodies().size(), 52u);
  EXPECT_EQ(w.bodies().position[50].x, 2.0);
  EXPECT_EQ(w.bodies().position[51].x, 19.0);
}

TEST(BodyOrder, MortonRerunsAreBitEqual) {
  auto run = [] {
    World w(pile(BodyOrder::Morton, 200));
    const auto solver = make_solver("pgs");
    SolverOptions o;
    o.max_sweeps = 100;
    for (int s = 0; s < 80; ++s) w.step(*solver, o);
    return state_hash(w.bodies());
  };
  EXPECT_EQ(run(), run());
}

constexpr double kFriction = 0.0;
TEST(BodyOrder, MortonAgreesWithCreationOrderToTheSolverTolerance) {
  // Same bodies, different numbering: the contact rows are solved in another Gauss–Seidel
  // order. Without friction the contact velocities are unique (the LCP is a convex QP in
  // them), so both orders approach the same step, up to what the solves leave unconverged
  // (with friction the bounded tangent rows of a redundant pile admit several solutions, and
  // the two orders pick different ones). The trajectory is chaotic (1e-15 grows to the size
  // of a body within a few hundred steps), so each step starts both worlds from the same
  // state (the creation world's, copied into the morton world by the numbering) and compares
  // one step: the velocity difference must stay below 1 % of what gravity adds in a step
  // (g Δt = 0.098 m/s), the position difference below Δt times that.
  WorldDef da = pile(BodyOrder::Creation, 200), db = pile(BodyOrder::Morton, 200);
  da.contact.friction = db.contact.friction = kFriction;
  World a(da), b(db);
  std::vector<std::size_t> slot(a.bodies().size());  // morton index of creation body k
  int matched = 0;
  for (std::size_t k = 0; k < slot.size(); ++k)
    for (std::size_t m = 0; m < slot.size(); ++m)
      if (a.bodies().position[k] == b.bodies().position[m]) slot[k] = m, ++matched;
  ASSERT_EQ(matched, 200);
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 5000;
  o.tolerance = 1e-10;
  double dx = 0, dv = 0, worst_theta = 0;
  std::size_t most_contacts = 0;
  for (int s = 0; s < 150; ++s) {
    for (std::size_t k = 0; k < slot.size(); ++k) {
      b.bodies().position[slot[k]] = a.bodies().position[k];
      b.bodies().velocity[slot[k]] = a.bodies().velocity[k];
      b.bodies().angle[slot[k]] = a.bodies().angle[k];
      b.bodies().omega[slot[k]] = a.bodies().omega[k];
    }
    const StepReport ra = a.step(*solver, o), rb = b.step(*solver, o);
    worst_theta = std::max({worst_theta, ra.solve.residual, rb.solve.residual});
    most_contacts = std::max(most_contacts, a.contacts().size());
    for (std::size_t k = 0; k < slot.size(); ++k) {
      dx = std::max(dx, length(a.bodies().position[k] - b.bodies().position[slot[k]]));
      dv = std::max(dv, length(a.bodies().velocity[k] - b.bodies().velocity[slot[k]]));
    }
  }
  std::printf("max one-step difference: %.3g m, %.3g m/s, worst residual %.3g\n", dx, dv, worst_theta);
  EXPECT_GT(most_contacts, 150u);  // the pile is in contact: the row order matters
  EXPECT_GT(dv, 0.0);               // the orders do differ (else this test checks nothing)
  const double gdt = length(a.def().world.gravity) * a.def().time.dt;
  EXPECT_LT(dv, 0.01 * gdt);
  EXPECT_LT(dx, 0.01 * gdt * a.def().time.dt);
}

TEST(BodyOrder, SceneKeyParsesAndRejectsUnknownOrders) {
  EXPECT_EQ(parse_scene("[bodies]\norder = \"morton\"\n").bodies.order, BodyOrder::Morton);
  EXPECT_EQ(parse_scene("").bodies.order, BodyOrder::Creation);
  EXPECT_THROW((void)parse_scene("[bodies]\norder = \"hilbert\"\n"), ConfigError);
  WorldDef d;
  apply_override(d, "bodies.order=\"morton\"");
  EXPECT_EQ(d.bodies.order, BodyOrder::Morton);
  EXPECT_EQ(parse_scene(scene_to_toml(d)).bodies.order, BodyOrder::Morton);
}

}  // namespace
}  // namespace dc
