// A and b of an assembled step checked against values computed independently of the assembly
// code: b from the velocities of the material contact points after a free step (v + ω × r,
// hand-written, plus the stabilisation formulas of docs/design.md §2), A as the impulse response
// Δt · (change of row i's point velocity per unit impulse of row j), with m = ρπr² and
// I = ½ m r² written out here — not A rebuilt from J.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "dc/engine/world.hpp"

namespace dc {
namespace {

struct Disc {
  Vec2 x, v;
  double omega = 0, r = 1, rho = 1;
  [[nodiscard]] double mass() const { return rho * std::numbers::pi * r * r; }
  [[nodiscard]] double inertia() const { return 0.5 * mass() * r * r; }
};

/// One row by hand: contact point p, direction d, bodies a (−1 for a wall) and b.
struct HandRow {
  int a = -1, b = 0;
  Vec2 p, d;
};

/// d · (velocity of the material point p of b − that of a), each v + ω × (p − x).
double point_velocity(const HandRow& row, const std::vector<Disc>& discs,
                      const std::vector<Vec2>& v, const std::vector<double>& omega) {
  auto at = [&](int k) {
    const Vec2 r = row.p - discs[static_cast<size_t>(k)].x;
    return v[static_cast<size_t>(k)] + omega[static_cast<size_t>(k)] * Vec2{-r.y, r.x};
  };
  double u = dot(row.d, at(row.b));
  if (row.a >= 0) u -= dot(row.d, at(row.a));
  return u;
}

TEST(AssemblyValues, AAndBEqualHandComputedImpulseResponses) {
  // Disc 0 in the bottom-left corner: 0.02 m into the floor (Baumgarte), 0.004 m from the left
  // wall (speculative); disc 1 leaning on it at 60°, 0.01 m away (speculative).
  const double dt = 0.01, beta = 0.2, slop = 0.005, mu = 0.5;
  const Vec2 g{0.0, -9.81};
  std::vector<Disc> discs(2);
  discs[0].x = {1.004, 0.98};
  discs[0].v = {0.3, -0.2};
  discs[0].omega = 0.5;
  const Vec2 n01{std::cos(std::numbers::pi / 3), std::sin(std::numbers::pi / 3)};
  discs[1].x = discs[0].x + 2.01 * n01;
  discs[1].v = {-1.0, -2.0};
  discs[1].omega = -0.7;

  WorldDef d;
  d.bodies.count = 0;
  d.contact.friction = mu;
  d.time.dt = dt;
  d.world.gravity = g;
  BodyState bodies;  // World(def, bodies): disc 0 starts inside the floor
  for (const Disc& c : discs) bodies.add(c.x, c.r, c.rho, c.v, 0.0, c.omega);
  World w(d, bodies);
  w.collide();
  const LcpProblem& p = w.assemble();
  ASSERT_EQ(w.contacts().size(), 3u);
  ASSERT_EQ(p.rows(), 6);

  // Hand geometry of each contact: normal from a to b, gap, point midway between surfaces.
  struct HandContact {
    ContactKey key;
    int a, b;
    Vec2 n;
    double gap;
  };
  const std::vector<HandContact> hand = {
      {ContactKey::wall(Wall::Bottom, 0), -1, 0, {0.0, 1.0}, discs[0].x.y - 1.0},
      {ContactKey::wall(Wall::Left, 0), -1, 0, {1.0, 0.0}, discs[0].x.x - 1.0},
      {ContactKey::pair(0, 1), 0, 1, n01, 0.01},
  };
  std::vector<HandRow> rows(6);
  std::vector<double> stab(6, 0.0);
  int floor_c = -1;
  for (const HandContact& h : hand) {
    int c = -1;
    for (int k = 0; k < 3; ++k)
      if (w.contacts()[static_cast<size_t>(k)].key == h.key) c = k;
    ASSERT_GE(c, 0) << "missing contact " << h.key.a << "," << h.key.b;
    if (h.key == hand[0].key) floor_c = c;
    const Contact& ct = w.contacts()[static_cast<size_t>(c)];
    EXPECT_NEAR(ct.gap, h.gap, 1e-12);
    const Vec2 point = discs[static_cast<size_t>(h.b)].x - (1.0 + 0.5 * h.gap) * h.n;
    EXPECT_NEAR(ct.point.x, point.x, 1e-12);
    EXPECT_NEAR(ct.point.y, point.y, 1e-12);
    const int rn = w.normal_row(c), rt = w.tangent_row(c);
    rows[static_cast<size_t>(rn)] = {h.a, h.b, point, h.n};
    rows[static_cast<size_t>(rt)] = {h.a, h.b, point, Vec2{-h.n.y, h.n.x}};
    stab[static_cast<size_t>(rn)] = h.gap > 0 ? h.gap / dt : beta * std::min(0.0, h.gap + slop) / dt;
    EXPECT_EQ(p.normal_row[static_cast<size_t>(rt)], rn);
    EXPECT_EQ(p.mu[rt], mu);
    EXPECT_EQ(p.lo[rn], 0.0);
  }
  // Baumgarte acts on the floor contact, the speculative term on the two others.
  EXPECT_NEAR(stab[static_cast<size_t>(w.normal_row(floor_c))], beta * (-0.02 + slop) / dt, 1e-12);

  // b: point velocities after a free step (v + Δt g, ω unchanged) plus stabilisation.
  std::vector<Vec2> v_free;
  std::vector<double> omega;
  for (const Disc& c : discs) {
    v_free.push_back(c.v + dt * g);
    omega.push_back(c.omega);
  }
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(p.b[i], point_velocity(rows[static_cast<size_t>(i)], discs, v_free, omega) + stab[static_cast<size_t>(i)],
                1e-12)
        << "b row " << i;

  // A: column j = Δt · point-velocity change of every row per unit impulse of row j.
  // A is formed on demand (the matrix-free pgs never needs it): form it here.
  const Eigen::MatrixXd A(w.ensure_assembled_matrix().A);
  for (int j = 0; j < 6; ++j) {
    const HandRow& rj = rows[static_cast<size_t>(j)];
    std::vector<Vec2> dv(2, Vec2{0.0, 0.0});
    std::vector<double> dw(2, 0.0);
    auto push = [&](int k, double sign) {
      const Disc& disc = discs[static_cast<size_t>(k)];
      dv[static_cast<size_t>(k)] = dv[static_cast<size_t>(k)] + (sign / disc.mass()) * rj.d;
      dw[static_cast<size_t>(k)] += sign * cross(rj.p - disc.x, rj.d) / disc.inertia();
    };
    push(rj.b, +1.0);
    if (rj.a >= 0) push(rj.a, -1.0);
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR(A(i, j), dt * point_velocity(rows[static_cast<size_t>(i)], discs, dv, dw), 1e-14)
          << "A(" << i << "," << j << ")";
  }
  // Two entries in closed form: a wall normal row sees 1/m; a tangent row of a touching
  // disc sees 1/m + r²/I = 3/m (the lever arm of the floor contact is r + gap/2).
  const int fn = w.normal_row(floor_c), ft = w.tangent_row(floor_c);
  const double m0 = discs[0].mass(), arm = 1.0 + 0.5 * (discs[0].x.y - 1.0);
  EXPECT_NEAR(A(fn, fn), dt / m0, 1e-15);
  EXPECT_NEAR(A(ft, ft), dt * (1.0 / m0 + arm * arm / (0.5 * m0)), 1e-14);
}

}  // namespace
}  // namespace dc
