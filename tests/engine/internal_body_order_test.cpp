// [bodies] internal_order = "morton": World steps its bodies in a re-sorted spatial order
// (internal_body_order.hpp) while every public view stays in the external order. Checked: the
// translation of contacts and rows, that a step agrees with the same step without the order to
// the solver's tolerance (frictionless: the contact velocities are unique), that everything
// public is consistent in external order, bit-equal reruns, user edits and appended bodies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dc/core/error.hpp"
#include "dc/engine/internal_body_order.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/step_outcome.hpp"
#include "dc/engine/world.hpp"
#include "previous_lambda_by_key.hpp"
#include "dc/engine/stress_scenes.hpp"

namespace dc {
namespace {

/// The scaled seed pile with an internal order or not.
WorldDef pile(InternalOrder internal_order, int n, int resort_every = 5) {
  WorldDef d = stress::scaled_seed_pile(n);
  d.bodies.internal_order = internal_order;
  d.bodies.resort_every = resort_every;
  return d;
}

TEST(InternalBodyOrder, TranslatesContactsToExternalKeysAndFlipsReversedPairs) {
  InternalBodyOrder order;
  BodyState s;
  // External bodies 0..3 on a line, backwards in x: the Morton resort reverses them.
  for (int k = 0; k < 4; ++k) s.add({10.0 - 2.0 * k, 1.0}, 1.0, 1.0);
  order.update_from(s, true);
  order.resort(2.0);
  EXPECT_EQ(order.external_of(), (std::vector<int>{3, 2, 1, 0}));
  EXPECT_EQ(order.state().position[0].x, 4.0);
  // Internal contacts: wall (bottom) with internal body 0, pair (0, 1) internal.
  Contact wall;
  wall.key = ContactKey::wall(Wall::Bottom, 0);
  wall.body_a = static_cast<int>(Wall::Bottom);
  wall.body_b = 0;
  wall.normal = {0, 1};
  Contact pair;
  pair.key = ContactKey::pair(0, 1);
  pair.body_a = 0;
  pair.body_b = 1;
  pair.normal = {1, 0};
  pair.lambda_t = 0.5;
  std::vector<Contact> external;
  std::vector<int> internal_of;
  order.external_order({pair, wall}, 4, internal_of);  // any internal order is sorted
  order.contacts_to_external({pair, wall}, internal_of, external);
  ASSERT_EQ(external.size(), 2u);
  EXPECT_EQ(external[0].key, ContactKey::wall(Wall::Bottom, 3));
  EXPECT_EQ(internal_of[0], 1);
  EXPECT_EQ(external[1].key, ContactKey::pair(2, 3));
  EXPECT_EQ(external[1].body_a, 2);
  EXPECT_EQ(external[1].normal.x, -1.0);  // from external body 2 (internal 1) to 3 (internal 0)
  EXPECT_EQ(external[1].lambda_t, 0.5);  // along the turned t, on the swapped bodies: the same force
  EXPECT_THROW(order.update_from(BodyState{}, false), InvalidArgument);  // bodies only appended
}

constexpr double kFrictionless = 0.0;
TEST(InternalBodyOrder, AStepAgreesWithTheExternalOrderToTheSolverTolerance) {
  // Both worlds start every step from the same state (the plain world's, written into the
  // other through bodies(): the edit path) and take one step; with internal order the
  // Gauss–Seidel row order differs, so agreement is to the solve's tolerance: velocity within
  // 1 % of g Δt, position within Δt times that (as BodyOrder.MortonAgreesWithCreationOrder…).
  WorldDef da = pile(InternalOrder::None, 300), db = pile(InternalOrder::Morton, 300);
  da.contact.friction = db.contact.friction = kFrictionless;
  World a(da), b(db);
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 5000;
  o.tolerance = 1e-10;
  double dx = 0, dv = 0;
  std::size_t most_contacts = 0;
  for (int s = 0; s < 150; ++s) {
    b.bodies().position = a.bodies().position;
    b.bodies().velocity = a.bodies().velocity;
    b.bodies().angle = a.bodies().angle;
    b.bodies().omega = a.bodies().omega;
    const StepReport ra = a.step(*solver, o, test::previous_lambda_by_key), rb = b.step(*solver, o, test::previous_lambda_by_key);
    ASSERT_EQ(ra.rows, rb.rows);
    ASSERT_EQ(a.contacts().size(), b.contacts().size());
    for (std::size_t c = 0; c < a.contacts().size(); ++c) ASSERT_EQ(a.contacts()[c].key, b.contacts()[c].key);
    for (int r = 0; r < ra.rows; ++r) ASSERT_NEAR(ra.solve.lambda[r], rb.solve.lambda[r], 1e-6) << "row " << r;
    most_contacts = std::max(most_contacts, a.contacts().size());
    for (std::size_t k = 0; k < a.bodies().size(); ++k) {
      dx = std::max(dx, length(a.bodies().position[k] - b.bodies().position[k]));
      dv = std::max(dv, length(a.bodies().velocity[k] - b.bodies().velocity[k]));
    }
  }
  std::printf("max one-step difference: %.3g m, %.3g m/s\n", dx, dv);
  EXPECT_GT(most_contacts, 200u);  // the pile is in contact: the row order matters
  EXPECT_GT(dv, 0.0);  // the row orders do differ
  const double gdt = length(a.def().world.gravity) * a.def().time.dt;
  EXPECT_LT(dv, 0.01 * gdt);
  EXPECT_LT(dx, 0.01 * gdt * a.def().time.dt);
}

TEST(InternalBodyOrder, PublicViewsAreInExternalOrder) {
  World plain(pile(InternalOrder::None, 300)), w(pile(InternalOrder::Morton, 300, 3));
  EXPECT_EQ(w.bodies().radius, plain.bodies().radius);
  EXPECT_EQ(state_hash(w.bodies()), state_hash(plain.bodies()));  // same start, same numbering
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 50;
  for (int s = 0; s < 100; ++s) {
    const StepReport r = w.step(*solver, o, test::previous_lambda_by_key);
    const World& cw = w;
    const BodyState& x = cw.bodies();
    ASSERT_EQ(r.rows, cw.problem().rows());
    (void)match_contacts_by_key(cw.contacts(), cw.contacts());  // throws unless sorted by key
    for (int c = 0; c < static_cast<int>(cw.contacts().size()); ++c) {
      const Contact& k = cw.contacts()[static_cast<std::size_t>(c)];
      EXPECT_EQ(r.solve.lambda[cw.normal_row(c)], k.lambda_n);
      if (cw.tangent_row(c) >= 0) {
        EXPECT_EQ(r.solve.lambda[cw.tangent_row(c)], k.lambda_t);
      }
      if (k.body_a < 0) continue;
      ASSERT_LT(k.body_a, k.body_b);
      // Geometry before the step: the normal points from a to b of the external bodies.
      EXPECT_EQ(cw.constraints()[c].body_a, k.body_a);
      const Vec2 d = x.position[static_cast<std::size_t>(k.body_b)] - x.position[static_cast<std::size_t>(k.body_a)];
      EXPECT_GT(dot(d, k.normal), 0.0);
    }
  }
  EXPECT_EQ(w.bodies().radius, plain.bodies().radius);  // constants stay with their bodies
  // The public stages: λ solved on problem() (external rows, friction on) and integrated
  // through the translation does what predict() says the public problem does with it.
  w.collide();
  w.assemble();
  const Eigen::VectorXd lambda = solver->solve(w.problem(), test::previous_lambda_by_key(w), o).lambda;
  StepOutcome predicted;
  w.predict(lambda, predicted);
  w.integrate(lambda);
  double dv = 0, dlambda_t = 0;
  for (std::size_t k = 0; k < w.bodies().size(); ++k)
    dv = std::max(dv, length(predicted.bodies.velocity[k] - w.bodies().velocity[k]));
  for (int c = 0; c < static_cast<int>(w.contacts().size()); ++c)
    if (w.tangent_row(c) >= 0) dlambda_t = std::max(dlambda_t, std::abs(lambda[w.tangent_row(c)]));
  EXPECT_GT(dlambda_t, 0.0);  // friction forces are present
  EXPECT_LT(dv, 1e-12);
}

TEST(InternalBodyOrder, RerunsAreBitEqualAndStagesMatchStep) {
  auto run = [](bool by_stages) {
    World w(pile(InternalOrder::Morton, 400, 7));
    const auto solver = make_solver("pgs");
    SolverOptions o;
    o.max_sweeps = 30;
    for (int s = 0; s < 60; ++s) {
      if (!by_stages) {
        w.step(*solver, o, test::previous_lambda_by_key);
        continue;
      }
      w.collide();
      w.assemble();
      w.integrate(solver->solve(w.problem(), test::previous_lambda_by_key(w), o).lambda);
    }
    return state_hash(w.bodies());
  };
  EXPECT_EQ(run(false), run(false));
  EXPECT_EQ(run(true), run(true));
  EXPECT_NE(run(false), state_hash(World(pile(InternalOrder::Morton, 400, 7)).bodies()));
}

TEST(InternalBodyOrder, InflowBodiesJoinTheInternalOrder) {
  WorldDef da = pile(InternalOrder::None, 100), db = pile(InternalOrder::Morton, 100);
  for (WorldDef* d : {&da, &db}) {
    d->inflow.rate = 200;
    d->inflow.stop = 10;
    d->inflow.region = {2, d->world.height - 6, d->world.width - 2, d->world.height - 2};
    d->contact.friction = kFrictionless;
  }
  World a(da), b(db);
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 2000;
  o.tolerance = 1e-10;
  for (int s = 0; s < 40; ++s) {
    b.bodies().position = a.bodies().position;
    b.bodies().velocity = a.bodies().velocity;
    a.step(*solver, o);
    b.step(*solver, o);
    ASSERT_EQ(a.bodies().size(), b.bodies().size()) << "step " << s;
  }
  EXPECT_GT(a.bodies().size(), 100u);
  double dv = 0;
  for (std::size_t k = 0; k < a.bodies().size(); ++k)
    dv = std::max(dv, length(a.bodies().velocity[k] - b.bodies().velocity[k]));
  EXPECT_LT(dv, 1e-3);
}

TEST(InternalBodyOrder, ExternalOrderFromConstraintsIsTheContactsOrder) {
  // 60 bodies on a line, backwards in x (the resort reverses them); internal contacts: every
  // wall with a few bodies, pairs with several features, and body 0 paired with 40 bodies (a
  // bucket beyond the insertion sort's), sorted by internal key as collide leaves them.
  InternalBodyOrder order;
  BodyState s;
  constexpr int n = 60;
  for (int k = 0; k < n; ++k) s.add({200.0 - 3.0 * k, 1.0 + (k % 3)}, 1.0, 1.0);
  order.update_from(s, true);
  order.resort(2.0);
  std::vector<Contact> internal;
  const auto add = [&](ContactKey key, int body_a) {
    Contact c;
    c.key = key;
    c.body_a = body_a;
    c.body_b = key.b;
    internal.push_back(c);
  };
  for (const Wall w : {Wall::Left, Wall::Right, Wall::Bottom, Wall::Top})
    for (int k = 0; k < n; k += 7) add(ContactKey::wall(w, k), static_cast<int>(w));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < std::min(n, i + (i == 0 ? 41 : 4)); ++j)
      for (int f = -1; f <= (j % 2); ++f) add(ContactKey::pair(i, j, f), i);
  std::sort(internal.begin(), internal.end(), [](const Contact& x, const Contact& y) { return x.key < y.key; });
  ContactConstraints assembled;
  for (const Contact& c : internal) assembled.add(c.body_a < 0 ? -1 : c.body_a, c.body_b, 0.5, c.key.feature);
  std::vector<int> by_contacts, by_constraints;
  order.external_order(internal, n, by_contacts);
  order.external_order(internal, assembled, n, by_constraints);
  EXPECT_EQ(by_constraints, by_contacts);
  std::vector<Contact> external;
  order.contacts_to_external(internal, by_constraints, external);
  for (std::size_t c = 1; c < external.size(); ++c) ASSERT_LT(external[c - 1].key, external[c].key) << c;
  assembled.add(-1, 0, 0.5);
  EXPECT_THROW(order.external_order(internal, assembled, n, by_constraints), InvalidArgument);
}

TEST(InternalBodyOrder, SceneKeysParseAndBadValuesAreConfigErrors) {
  const WorldDef d =
      parse_scene("[bodies]\ninternal_order = \"morton\"\nresort_every = 7\nresort_decay = 1.25\n");
  EXPECT_EQ(d.bodies.internal_order, InternalOrder::Morton);
  EXPECT_EQ(d.bodies.resort_every, 7);
  EXPECT_EQ(d.bodies.resort_decay, 1.25);
  EXPECT_EQ(parse_scene(scene_to_toml(d)).bodies.resort_decay, 1.25);
  EXPECT_THROW((void)parse_scene("[bodies]\nresort_decay = 0.5\n"), ConfigError);
  EXPECT_EQ(parse_scene("").bodies.internal_order, InternalOrder::Auto);  // the default
  EXPECT_EQ(parse_scene(scene_to_toml(d)).bodies.resort_every, 7);
  EXPECT_THROW((void)parse_scene("[bodies]\ninternal_order = \"hilbert\"\n"), ConfigError);
  EXPECT_THROW((void)parse_scene("[bodies]\nresort_every = 0\n"), ConfigError);
  WorldDef boxes = pile(InternalOrder::Morton, 20);
  boxes.bodies.shape = BodyShape::Box;
  EXPECT_THROW((void)World(boxes), ConfigError);
}

}  // namespace
}  // namespace dc
