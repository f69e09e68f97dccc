// pgs-colored's layout scans on the team (solvers/pgs_colored/setup/layout_scan.hpp): the
// dynamic bodies, the first badly bounded normal row and the greedy two-point manifolds, the
// same on every thread count as one pass in contact order computes them.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "dc/engine/world.hpp"
#include "solvers/pgs_colored/setup/layout_scan.hpp"

namespace dc {
namespace {

/// `stacks` columns of `height` 1 × 1 m boxes resting on the floor and on each other: every box
/// face on another (or the floor) is a two-point manifold. Collided and assembled as placed.
LcpProblem stacks_problem(int stacks, int height) {
  WorldDef d;
  d.bodies.count = 0;
  d.world.width = 1.5 * stacks + 4;
  d.world.height = height + 4.0;
  d.world.walls = {false, false, true, false};
  d.contact.friction = 0.5;
  for (int s = 0; s < stacks; ++s)
    for (int row = 0; row < height; ++row) {
      BodyDef b;
      b.shape = BodyShape::Box;
      b.size = {1, 1};
      b.position = {2 + 1.5 * s, 0.5 + row};
      d.body.push_back(b);
    }
  World w(d);
  w.collide();
  return w.assemble();
}

struct Scan {
  std::vector<std::uint8_t> dynamic;
  std::vector<int> partner;
  int bad = -1;
};

/// The scans in one pass in contact order, from may_pair (the pairing's own test).
Scan serial_scan(const LcpProblem& p, int bodies) {
  Scan s;
  s.dynamic.assign(static_cast<size_t>(bodies), 0);
  for (int c = 0; c < static_cast<int>(p.inv_mass.size()); ++c)
    if (p.inv_mass[c] != 0.0) s.dynamic[static_cast<size_t>(c / 3)] = 1;
  const int nc = p.constraints.size();
  for (int c = 0; c < nc && s.bad < 0; ++c) {
    const int i = p.constraints[c].normal_row;
    if (p.lo[i] != 0.0 || p.hi[i] != std::numeric_limits<double>::infinity()) s.bad = c;
  }
  s.partner.assign(static_cast<size_t>(nc), -1);
  for (int c = 0; c + 1 < nc; ++c)
    if (colored::may_pair(p, c)) {
      s.partner[static_cast<size_t>(c)] = c + 1;
      s.partner[static_cast<size_t>(++c)] = -2;
    }
  return s;
}

Scan team_scan(const LcpProblem& p, int bodies, int threads) {
  Scan s;
  s.partner.assign(static_cast<size_t>(p.constraints.size()), 7);  // stale values, overwritten
  s.bad = colored::scan_contacts(p, bodies, threads, s.dynamic, s.partner);
  return s;
}

TEST(PgsColoredLayoutScan, EveryThreadCountScansAsOnePassInContactOrder) {
  LcpProblem p = stacks_problem(200, 14);
  const int bodies = static_cast<int>(p.J.cols() / 3);
  const int nc = p.constraints.size();
  ASSERT_GT(nc, 5 * 1024) << "enough contacts for five parts";
  const Scan one = serial_scan(p, bodies);
  int pairs = 0;
  for (const int q : one.partner) pairs += q >= 0 ? 1 : 0;
  ASSERT_GT(pairs, nc / 3) << "the stacks rest on two-point manifolds";
  ASSERT_EQ(one.bad, -1);
  for (const int threads : {1, 2, 3, 4, 5}) {
    const Scan got = team_scan(p, bodies, threads);
    EXPECT_EQ(one.dynamic, got.dynamic) << threads << " threads";
    EXPECT_EQ(one.partner, got.partner) << threads << " threads";
    EXPECT_EQ(-1, got.bad) << threads << " threads";
  }
  // Two normal rows bounded otherwise, in the last part: the first of them is named.
  for (const int c : {nc - 5, nc - 2}) p.lo[p.constraints[c].normal_row] = -1.0;
  for (const int threads : {1, 2, 5}) EXPECT_EQ(nc - 5, team_scan(p, bodies, threads).bad) << threads << " threads";
}

}  // namespace
}  // namespace dc
