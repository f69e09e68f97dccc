// Relationships the engine must satisfy (docs/design.md §2–3): physical sanity values, assembly
// identities, broad phase ≡ brute force, determinism, conservation laws.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "collision/narrow_phase.hpp"
#include "dc/engine/broad_phase.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "settled_pile.hpp"

namespace dc {
namespace {

WorldDef single_circle_on_floor(double mu) {
  WorldDef d;
  d.bodies.count = 0;
  d.contact.friction = mu;
  BodyDef b;
  b.position = {15.0, 1.0};  // resting exactly on the floor (gap 0)
  d.body.push_back(b);
  return d;
}

SolverOptions tight(int sweeps = 2000) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = 1e-12;
  return o;
}

TEST(World, RestingCircleCarriesItsWeight) {
  for (double mu : {0.0, 0.5}) {
    World w(single_circle_on_floor(mu));
    const auto solver = make_solver("pgs");
    for (int s = 0; s < 50; ++s) w.step(*solver, tight());
    ASSERT_EQ(w.contacts().size(), 1u);
    const double m = std::numbers::pi;  // ρ = 1, r = 1
    EXPECT_NEAR(w.contacts()[0].lambda_n, m * 9.81, 1e-6 * m * 9.81) << "mu=" << mu;
    EXPECT_NEAR(w.contacts()[0].lambda_t, 0.0, 1e-9);
    EXPECT_NEAR(w.bodies().position[0].y, 1.0, 1e-9);
    EXPECT_NEAR(w.bodies().velocity[0].y, 0.0, 1e-9);
  }
}

TEST(World, AssembledMatrixEqualsJMinvJtDt) {
  World w{WorldDef{}};
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 50;
  for (int s = 0; s < 150; ++s) w.step(*solver, o);  // let them fall and touch
  w.collide();
  EXPECT_FALSE(w.assemble().has_assembled_matrix());  // A only on demand
  const LcpProblem& p = w.ensure_assembled_matrix();
  ASSERT_GT(p.rows(), 20);
  const Eigen::MatrixXd J(p.J);
  const Eigen::MatrixXd A = J * p.inv_mass.asDiagonal() * J.transpose() * p.dt;
  EXPECT_LE((Eigen::MatrixXd(p.A) - A).cwiseAbs().maxCoeff(), 1e-12 * A.cwiseAbs().maxCoeff());
  // Friction rows are coupled to the normal row just before them.
  for (int c = 0; c < static_cast<int>(w.contacts().size()); ++c) {
    EXPECT_EQ(p.normal_row[static_cast<size_t>(w.tangent_row(c))], w.normal_row(c));
    EXPECT_EQ(p.mu[w.tangent_row(c)], w.def().contact.friction);
  }
  // b is the relative velocity after a free step plus stabilisation: compare one contact.
  const Contact& c0 = w.contacts()[0];
  EXPECT_TRUE(c0.key.is_wall() || c0.key.a < c0.key.b);
}

TEST(World, NoTangentRowsWithoutFriction) {
  WorldDef d;
  d.contact.friction = 0.0;
  World w(d);
  const LcpProblem& p = test::step_then_assemble(w, 150, 20);
  EXPECT_EQ(p.rows(), static_cast<int>(w.contacts().size()));
  for (int r : p.normal_row) EXPECT_EQ(r, -1);
}

TEST(World, ContactsAreSortedByKeyAndUnique) {
  World w{WorldDef{}};
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 30;
  for (int s = 0; s < 200; ++s) w.step(*solver, o);
  const auto& cs = w.collide();
  ASSERT_GT(cs.size(), 50u);
  for (std::size_t i = 1; i < cs.size(); ++i) EXPECT_LT(cs[i - 1].key, cs[i].key);
  for (const Contact& c : cs) {
    EXPECT_NEAR(length(c.normal), 1.0, 1e-12);
    if (!c.key.is_wall()) {
      EXPECT_LT(c.key.a, c.key.b);
    }
  }
}

// match_contacts_by_key against a brute-force search, on consecutive steps of a real scene;
// lists out of key order are refused.
TEST(World, MatchContactsByKeyEqualsBruteForce) {
  WorldDef def;
  def.bodies.count = 60;
  World w(def);
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 30;
  int persistent = 0, fresh = 0;
  for (int s = 0; s < 200; ++s) {
    w.collide();
    const LcpProblem& p = w.assemble();
    const auto& cur = w.contacts();
    const auto& prev = w.previous_contacts();
    const std::vector<int> m = match_contacts_by_key(prev, cur);
    ASSERT_EQ(m.size(), cur.size());
    for (std::size_t c = 0; c < cur.size(); ++c) {
      int want = -1;
      for (std::size_t j = 0; j < prev.size(); ++j)
        if (prev[j].key == cur[c].key) want = static_cast<int>(j);
      ASSERT_EQ(m[c], want) << "step " << s << " contact " << c;
      (want >= 0 ? persistent : fresh) += 1;
    }
    w.integrate(solver->solve(p, Eigen::VectorXd::Zero(p.rows()), o).lambda);
  }
  EXPECT_GT(persistent, 100);
  EXPECT_GT(fresh, 10);
  Contact a, b;
  a.key = ContactKey::pair(0, 1);
  b.key = ContactKey::pair(0, 2);
  const std::vector<Contact> sorted{a, b}, unsorted{b, a};
  EXPECT_EQ(match_contacts_by_key(sorted, sorted), (std::vector<int>{0, 1}));
  EXPECT_THROW(match_contacts_by_key(unsorted, sorted), InvalidArgument);
  EXPECT_THROW(match_contacts_by_key(sorted, unsorted), InvalidArgument);
}

TEST(World, BroadPhaseFindsExactlyTheBruteForcePairs) {
  Rng rng(7);
  UniformGridBroadPhase reused;  // its buffers carry over from trial to trial (sizes up and down)
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 1 + static_cast<int>(rng.uniform_int(300));
    std::vector<Vec2> x(static_cast<size_t>(n));
    std::vector<double> r(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) {
      x[static_cast<size_t>(k)] = {rng.uniform(0, 40), rng.uniform(0, 25)};
      r[static_cast<size_t>(k)] = rng.uniform(0.05, trial % 3 == 0 ? 4.0 : 1.0);
    }
    std::vector<std::pair<int, int>> got, want;
    UniformGridBroadPhase bp;
    bp.find_pairs(x, r, got);
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b) {
        const auto ia = static_cast<size_t>(a), ib = static_cast<size_t>(b);
        if (std::abs(x[ia].x - x[ib].x) <= r[ia] + r[ib] && std::abs(x[ia].y - x[ib].y) <= r[ia] + r[ib])
          want.emplace_back(a, b);
      }
    EXPECT_EQ(got, want) << "trial " << trial << " n=" << n;
    std::vector<std::pair<int, int>> again;
    reused.find_pairs(x, r, again);
    EXPECT_EQ(again, want) << "reused, trial " << trial << " n=" << n;
  }
}

TEST(World, CircleProbesGiveTheSameContactsAsTheBodyArrays) {
  // collide() reads pairs through packed records (circle_probe.hpp): the contacts must be
  // those of the body arrays, bit for bit.
  Rng rng(11);
  BodyState s;
  for (int k = 0; k < 60; ++k)
    s.add({rng.uniform(0, 12), rng.uniform(0, 12)}, rng.uniform(0.3, 1.2), 1.0,
          {rng.uniform(-30, 30), rng.uniform(-30, 30)});
  const WorldDef def;
  std::vector<CircleProbe> probe(s.size());
  for (std::size_t k = 0; k < s.size(); ++k)
    probe[k] = {s.position[k], s.radius[k], speculative_reach(s, static_cast<int>(k), def.contact, def.time.dt)};
  int contacts = 0;
  for (int a = 0; a < static_cast<int>(s.size()); ++a)
    for (int b = a + 1; b < static_cast<int>(s.size()); ++b) {
      const auto ia = static_cast<size_t>(a), ib = static_cast<size_t>(b);
      const auto want = circle_circle(s, a, b, probe[ia].spec + probe[ib].spec);
      const auto got = circle_circle(probe[ia], probe[ib], a, b);
      ASSERT_EQ(got.has_value(), want.has_value()) << a << "," << b;
      if (!want) continue;
      ++contacts;
      EXPECT_EQ(got->key, want->key);
      EXPECT_EQ(got->normal, want->normal);
      EXPECT_EQ(got->point, want->point);
      EXPECT_EQ(got->gap, want->gap);
    }
  EXPECT_GT(contacts, 20);
}

TEST(World, GenerationIsSeededAndValid) {
  WorldDef d;
  const BodyState a = make_bodies(d), b = make_bodies(d);
  EXPECT_EQ(state_hash(a), state_hash(b));
  d.bodies.seed = 2;
  EXPECT_NE(state_hash(make_bodies(d)), state_hash(a));
  ASSERT_EQ(a.size(), 100u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_GE(a.position[i].x, 1.0);
    EXPECT_LE(a.position[i].x, 29.0);
    EXPECT_GE(a.position[i].y, 1.0);
    EXPECT_LE(a.position[i].y, 29.0);
    for (std::size_t j = 0; j < i; ++j) EXPECT_GE(length(a.position[i] - a.position[j]), 2.0);
  }
}

TEST(World, ExplicitBodiesAreCheckedAndNamed) {
  WorldDef d;
  d.bodies.count = 0;
  BodyDef b;
  b.position = {5, 5};
  d.body = {b, b};
  try {
    World w(d);
    FAIL() << "overlap accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("#2 at (5, 5)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("overlaps [[body]] #1"), std::string::npos) << e.what();
  }
  d.body = {b};
  d.body[0].position = {0.5, 5};
  EXPECT_THROW(World{d}, ConfigError);
  d.body[0].position = {5, 5};
  d.bodies.count = 500;  // cannot fit 500 unit circles in a Gaussian blob of σ = 0.1
  d.bodies.sigma = 0.1;
  d.bodies.max_attempts = 2000;
  EXPECT_THROW(World{d}, ConfigError);
}

TEST(World, TwoIdenticalRunsAreBitEqual) {
  auto run = [] {
    World w{WorldDef{}};
    const auto solver = make_solver("pgs");
    SolverOptions o;
    o.max_sweeps = 100;
    for (int s = 0; s < 120; ++s) w.step(*solver, o);
    return state_hash(w.bodies());
  };
  EXPECT_EQ(run(), run());
}

TEST(World, FreeBodiesConserveLinearMomentum) {
  WorldDef d;
  d.world.walls = {false, false, false, false};
  d.world.gravity = {0, 0};
  d.bodies.count = 40;
  d.bodies.sigma = 3.0;
  BodyDef fast;
  fast.position = {2.0, 15.0};
  fast.velocity = {30.0, 0.5};
  fast.radius = 1.5;
  d.body.push_back(fast);
  World w(d);
  auto momentum = [&] {
    Vec2 p;
    for (std::size_t k = 0; k < w.bodies().size(); ++k) p += w.bodies().mass[k] * w.bodies().velocity[k];
    return p;
  };
  const Vec2 p0 = momentum();
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 200;
  int touched = 0;
  for (int s = 0; s < 100; ++s) touched += w.step(*solver, o).contacts > 0;
  EXPECT_GT(touched, 10);
  const Vec2 p1 = momentum();
  const double scale = w.bodies().mass.back() * 30.0;
  EXPECT_NEAR(p1.x, p0.x, 1e-9 * scale);
  EXPECT_NEAR(p1.y, p0.y, 1e-9 * scale);
}

TEST(World, EnergyDoesNotGrowWithoutRestitution) {
  World w{WorldDef{}};
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 500;
  o.tolerance = 1e-6;
  double e0 = w.kinetic_energy() + w.potential_energy();
  double worst = 0;
  for (int s = 0; s < 300; ++s) {
    w.step(*solver, o);
    const double e = w.kinetic_energy() + w.potential_energy();
    worst = std::max(worst, e - e0);
    e0 = std::min(e0, e);
  }
  // Baumgarte pushes penetrating bodies apart, which can add a little energy; bound it by a
  // small fraction of the potential energy scale (m g H for one body).
  EXPECT_LT(worst, 0.05 * std::numbers::pi * 9.81 * 30);
}

TEST(World, AssembledJacobianIsTheMatrixOfItsOwnTriplets) {
  // assemble() fills J's compressed rows in place: each row must hold its contact's bodies'
  // columns once, in ascending order (3 entries for a wall contact, 6 for a pair), and equal
  // the matrix Eigen builds from the same triplets (which sorts and merges), step after step
  // as the contacts change.
  WorldDef def;
  def.bodies.count = 60;
  World w(def);
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 20;
  int checked = 0;
  for (int s = 0; s < 250; ++s) {
    w.step(*solver, o);
    if (s % 25 != 0 || w.problem().rows() == 0) continue;
    const SparseRowMatrix& J = w.problem().J;
    ASSERT_TRUE(J.isCompressed());
    std::vector<Eigen::Triplet<double, int>> trip;
    for (int c = 0; c < w.constraints().size(); ++c) {
      const ContactConstraint& k = w.constraints()[c];
      for (const int row : {k.normal_row, k.tangent_row}) {
        if (row < 0) continue;
        const int first = J.outerIndexPtr()[row], last = J.outerIndexPtr()[row + 1];
        ASSERT_EQ(last - first, k.has_body_a() ? 6 : 3) << "row " << row;
        std::vector<int> want;
        for (const int body : {k.body_a, k.body_b})
          if (body >= 0)
            for (int d = 0; d < 3; ++d) want.push_back(3 * body + d);
        std::sort(want.begin(), want.end());
        for (int e = first; e < last; ++e) {
          EXPECT_EQ(J.innerIndexPtr()[e], want[static_cast<size_t>(e - first)]) << "row " << row;
          trip.emplace_back(row, J.innerIndexPtr()[e], J.valuePtr()[e]);
        }
      }
    }
    SparseRowMatrix ref(J.rows(), J.cols());
    ref.setFromTriplets(trip.begin(), trip.end());
    ASSERT_EQ(ref.nonZeros(), J.nonZeros());
    EXPECT_EQ(Eigen::MatrixXd(ref - J).cwiseAbs().maxCoeff(), 0.0);
    ++checked;
  }
  EXPECT_GT(checked, 3);
}

}  // namespace
}  // namespace dc
