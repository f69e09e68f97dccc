// The lazy public views of `[bodies] internal_order = "morton"` (world.hpp) and its re-sort when
// the order has decayed. Checked: the views built on first read equal what the eager boundary
// built — the public problem bit for bit equal to assembling the public contacts on the public
// bodies, previous_contacts() bit for bit the contacts read at the end of the last step (across
// re-sorts, which re-key the internal memory) —; reading views or not, and the engine's builtin
// warm start against the same warm start written as a guess function, give bit-equal
// trajectories; the decay measure re-sorts a moving pile and leaves the order alone otherwise.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>

#include "dc/core/error.hpp"
#include "dc/engine/internal_body_order.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "assembly/assembly.hpp"
#include "previous_lambda_by_key.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "bytes_equal.hpp"

namespace dc {
namespace {

WorldDef pile(int n, int resort_every, double restitution = 0.0) {
  WorldDef d = stress::scaled_seed_pile(n);
  d.bodies.internal_order = InternalOrder::Morton;
  d.bodies.resort_every = resort_every;
  d.contact.restitution = restitution;
  return d;
}

bool same_bits(double x, double y) { return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y); }

::testing::AssertionResult same_bits(const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::Ref<const Eigen::VectorXd>& y) {
  if (x.size() != y.size()) return ::testing::AssertionFailure() << "sizes " << x.size() << " / " << y.size();
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (!same_bits(x[i], y[i])) return ::testing::AssertionFailure() << "entry " << i << ": " << x[i] << " / " << y[i];
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult same_bits(const Contact& x, const Contact& y) {
  const bool same = x.key == y.key && x.body_a == y.body_a && x.body_b == y.body_b && same_bits(x.point.x, y.point.x) &&
                    same_bits(x.point.y, y.point.y) && same_bits(x.normal.x, y.normal.x) &&
                    same_bits(x.normal.y, y.normal.y) && same_bits(x.gap, y.gap) &&
                    same_bits(x.lambda_n, y.lambda_n) && same_bits(x.lambda_t, y.lambda_t) &&
                    same_bits(x.approach_velocity, y.approach_velocity) && x.restitution_due == y.restitution_due &&
                    same_bits(x.anchor_a.x, y.anchor_a.x) && same_bits(x.anchor_b.y, y.anchor_b.y);
  if (same) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "contacts (" << x.key.a << ", " << x.key.b << ") / (" << y.key.a << ", "
                                       << y.key.b << ") differ";
}

::testing::AssertionResult same_bits(const std::vector<Contact>& x, const std::vector<Contact>& y) {
  if (x.size() != y.size()) return ::testing::AssertionFailure() << "sizes " << x.size() << " / " << y.size();
  for (std::size_t c = 0; c < x.size(); ++c)
    if (auto r = same_bits(x[c], y[c]); !r) return r << " at " << c;
  return ::testing::AssertionSuccess();
}

/// Everything of two assembled problems, bit for bit (J's compressed arrays included).
void expect_same_problem(const LcpProblem& p, const LcpProblem& q) {
  ASSERT_EQ(p.rows(), q.rows());
  EXPECT_TRUE(same_bits(p.b, q.b));
  EXPECT_TRUE(same_bits(p.lo, q.lo));
  EXPECT_TRUE(same_bits(p.hi, q.hi));
  EXPECT_TRUE(same_bits(p.mu, q.mu));
  EXPECT_TRUE(same_bits(p.inv_mass, q.inv_mass));
  EXPECT_EQ(p.normal_row, q.normal_row);
  EXPECT_TRUE(same_bits(p.dt, q.dt));
  ASSERT_EQ(p.J.cols(), q.J.cols());
  ASSERT_EQ(p.J.nonZeros(), q.J.nonZeros());
  const auto nnz = static_cast<std::size_t>(p.J.nonZeros());
  EXPECT_TRUE(test::bytes_equal(p.J.outerIndexPtr(), q.J.outerIndexPtr(), static_cast<std::size_t>(p.rows() + 1)));
  EXPECT_TRUE(test::bytes_equal(p.J.innerIndexPtr(), q.J.innerIndexPtr(), nnz));
  EXPECT_TRUE(test::bytes_equal(p.J.valuePtr(), q.J.valuePtr(), nnz));
  ASSERT_EQ(p.constraints.size(), q.constraints.size());
  for (int c = 0; c < p.constraints.size(); ++c) {
    const ContactConstraint &x = p.constraints[c], &y = q.constraints[c];
    EXPECT_EQ(x.normal_row, y.normal_row);
    EXPECT_EQ(x.tangent_row, y.tangent_row);
    EXPECT_EQ(x.body_a, y.body_a);
    EXPECT_EQ(x.body_b, y.body_b);
    EXPECT_TRUE(same_bits(x.mu, y.mu));
    EXPECT_EQ(x.feature, y.feature);
  }
}

/// The builtin warm start written out over the public views (what the warmstart library's
/// `builtin` computes).
Eigen::VectorXd builtin_over_public_views(const World& w) {
  Eigen::VectorXd out = test::previous_lambda_by_key(w);
  project_feasible(w.problem(), out);
  return out;
}

/// Steps three worlds of one definition side by side: `inside` reads every view inside its
/// guess (checked against the eager reference; its previous contacts are rebuilt from the
/// engine's memory), `after` reads the contacts and bodies after each step (its previous
/// contacts are those views kept), `blind` reads nothing until the end; both take the engine's
/// warm start. Returns the number of re-sorts.
int run_side_by_side(const WorldDef& def, int steps) {
  World inside(def), after(def), blind(def);
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 20;
  o.tolerance = 0;
  std::vector<Contact> last_contacts;  // after.contacts() at the end of the last step
  for (int s = 0; s < steps; ++s) {
    const StepReport ri = inside.step(*solver, o, [&](const World& w) {
      EXPECT_TRUE(same_bits(w.previous_contacts(), last_contacts)) << "step " << s;
      LcpProblem eager;  // the eager boundary: the public contacts assembled on the public bodies
      assemble_lcp(w.bodies(), w.contacts(), w.def(), eager);
      expect_same_problem(w.problem(), eager);
      return builtin_over_public_views(w);
    });
    const StepReport ra = after.step(*solver, o, World::WarmStart::PreviousLambda);
    const StepReport rb = blind.step(*solver, o, World::WarmStart::PreviousLambda);
    EXPECT_TRUE(same_bits(ri.solve.lambda, ra.solve.lambda)) << "step " << s;
    EXPECT_TRUE(same_bits(ra.solve.lambda, rb.solve.lambda)) << "step " << s;
    last_contacts = after.contacts();
    for (int c = 0; c < static_cast<int>(last_contacts.size()); ++c) {
      EXPECT_TRUE(same_bits(last_contacts[static_cast<std::size_t>(c)].lambda_n, ra.solve.lambda[after.normal_row(c)]));
    }
    (void)after.bodies();
  }
  EXPECT_EQ(state_hash(inside.bodies()), state_hash(blind.bodies()));
  EXPECT_EQ(state_hash(after.bodies()), state_hash(blind.bodies()));
  EXPECT_TRUE(same_bits(after.contacts(), blind.contacts()));
  EXPECT_TRUE(same_bits(inside.contacts(), blind.contacts()));
  EXPECT_EQ(after.internal_order_resorts(), blind.internal_order_resorts());
  return blind.internal_order_resorts();
}

TEST(InternalBodyOrderLazy, ViewsEqualTheEagerOnesAndReadingThemChangesNothing) {
  EXPECT_GT(run_side_by_side(pile(400, 3), 40), 10);  // re-sorts (and re-keys) every 3 steps
}

TEST(InternalBodyOrderLazy, WithRestitutionTheSameHolds) {
  // e > 0 reads the public contacts inside collide() (approach velocities by external key).
  EXPECT_GT(run_side_by_side(pile(300, 4, 0.5), 30), 5);
}

TEST(InternalBodyOrderLazy, TheEngineWarmStartIsTheBuiltinOneWithoutAnOrder) {
  WorldDef d = stress::scaled_seed_pile(300);
  World a(d), b(d);
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 20;
  for (int s = 0; s < 30; ++s) {
    const StepReport ra = a.step(*solver, o, builtin_over_public_views);
    const StepReport rb = b.step(*solver, o, World::WarmStart::PreviousLambda);
    ASSERT_TRUE(same_bits(ra.solve.lambda, rb.solve.lambda)) << "step " << s;
  }
  EXPECT_EQ(state_hash(a.bodies()), state_hash(b.bodies()));
  EXPECT_EQ(a.internal_order_resorts(), 0);
}

TEST(InternalBodyOrderLazy, RekeyKeepsTheExternalViewOfContacts) {
  InternalBodyOrder order;
  BodyState s;
  for (int k = 0; k < 4; ++k) s.add({1.0 + 2.0 * k, 1.0}, 1.0, 1.0);  // sorted along x already
  order.update_from(s, true);
  order.resort(2.0);
  Contact pair;  // internal pair (1, 2), normal from 1 to 2
  pair.key = ContactKey::pair(1, 2);
  pair.body_a = 1;
  pair.body_b = 2;
  pair.normal = {1, 0};
  pair.anchor_a = {0.5, 0};
  pair.anchor_b = {-0.5, 0};
  pair.lambda_n = 2;
  Contact wall;
  wall.key = ContactKey::wall(Wall::Left, 3);
  wall.body_a = static_cast<int>(Wall::Left);
  wall.body_b = 3;
  wall.normal = {1, 0};
  std::vector<Contact> internal{wall, pair}, before, after;
  std::vector<int> of;
  order.external_order(internal, 4, of);
  order.contacts_to_external(internal, of, before);
  // Move the bodies backwards along x: the next resort reverses the internal order.
  for (int k = 0; k < 4; ++k) order.state().position[static_cast<std::size_t>(k)].x = 10.0 - 2.0 * k;
  order.resort(2.0);
  order.rekey(internal);
  EXPECT_EQ(internal[0].key, ContactKey::wall(Wall::Left, 0));  // was internal body 3
  EXPECT_EQ(internal[1].key, ContactKey::pair(1, 2));            // 2 → 1, 1 → 2: turned
  EXPECT_EQ(internal[1].normal.x, -1.0);
  order.external_order(internal, 4, of);
  order.contacts_to_external(internal, of, after);
  EXPECT_TRUE(same_bits(before, after));
}

TEST(InternalBodyOrderLazy, AMovingPileIsResortedWhenItsOrderDecays) {
  // A wide cloud (σ = a fifth of the box) falls onto the floor: bodies move by many diameters,
  // so the pairs in contact spread over the order and the decay measure re-sorts it well before
  // the upper bound of 10,000 steps. With an unreachable threshold the order is sorted once.
  auto resorts = [](double decay) {
    WorldDef d = pile(400, 10000);
    d.bodies.sigma = d.world.width / 5;
    d.bodies.resort_decay = decay;
    World w(d);
    const auto solver = make_solver("pgs");
    SolverOptions o;
    o.max_sweeps = 10;
    for (int s = 0; s < 150; ++s) w.step(*solver, o, World::WarmStart::PreviousLambda);
    return w.internal_order_resorts();
  };
  EXPECT_EQ(resorts(1e9), 1);
  EXPECT_GT(resorts(1.5), 1);
  EXPECT_GE(resorts(1.1), resorts(1.5));
  WorldDef bad = pile(10, 5);
  bad.bodies.resort_decay = 1.0;
  EXPECT_THROW(bad.validate(), ConfigError);
}

}  // namespace
}  // namespace dc
