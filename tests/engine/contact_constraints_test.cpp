// ContactConstraints (rows, bodies and μ per contact), its scatter/gather helpers, the
// matrix-free PGS on problems mixing frictionless and frictional contacts, A on demand, and
// the one integrator (predict_step ≡ World::integrate).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/contact_match.hpp"
#include "dc/lcp/contact_constraints.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "lcp/solver_test_problems.hpp"

namespace dc {
namespace {

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

/// A world of `def` after `steps` steps of `solver` with `sweeps` sweeps (the pile has formed).
World stepped(const WorldDef& def, const char* solver, int steps, int sweeps) {
  World w(def);
  const auto s = make_solver(solver);
  SolverOptions o;
  o.max_sweeps = sweeps;
  for (int k = 0; k < steps; ++k) w.step(*s, o);
  return w;
}

SolveResult run(const char* name, const LcpProblem& p, int sweeps) {
  SolverOptions o;
  o.max_sweeps = sweeps;
  o.tolerance = 0.0;
  return make_solver(name)->solve(p, Eigen::VectorXd(), o);
}

TEST(ContactConstraints, RowsFollowEachContactsFriction) {
  ContactConstraints k;
  EXPECT_EQ(k.add(0, 1, 0.5), 0);
  EXPECT_EQ(k.add(-1, 2, 0.0, 3), 1);
  EXPECT_EQ(k.add(2, 1, 0.3), 2);
  EXPECT_EQ(k.add(-1, 0, 0.0), 3);
  ASSERT_EQ(k.size(), 4);
  EXPECT_EQ(k.rows(), 6);
  const int normal[] = {0, 2, 3, 5}, tangent[] = {1, -1, 4, -1};
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(k[c].normal_row, normal[c]) << c;
    EXPECT_EQ(k[c].tangent_row, tangent[c]) << c;
    EXPECT_EQ(k[c].has_friction(), tangent[c] >= 0) << c;
  }
  EXPECT_EQ(k[1].body_a, -1);
  EXPECT_FALSE(k[1].has_body_a());
  EXPECT_EQ(k[1].feature, 3);
  EXPECT_EQ(k[2].mu, 0.3);
  EXPECT_THROW(k.add(0, -1, 0.1), InvalidArgument);
  EXPECT_THROW(k.add(1, 1, 0.1), InvalidArgument);
  EXPECT_THROW(k.add(-2, 1, 0.1), InvalidArgument);
  EXPECT_THROW(k.add(0, 1, -0.1), InvalidArgument);
  EXPECT_THROW(k.add(0, 1, NAN), InvalidArgument);
  ContactConstraint bad{.normal_row = 6, .tangent_row = -1, .body_a = 0, .body_b = 1, .mu = 0.2};
  EXPECT_THROW(k.add(bad), InvalidArgument);  // μ > 0 needs a tangent row
  EXPECT_EQ(k.size(), 4);
  EXPECT_EQ(k.rows(), 6);
  k.clear();
  EXPECT_TRUE(k.empty());
  EXPECT_EQ(k.rows(), 0);
}

TEST(ContactConstraints, GatherAndScatterAreInverse) {
  test::TestRng rng(3);
  ContactConstraints k;
  for (int c = 0; c < 40; ++c) k.add(c % 7 == 0 ? -1 : c, c + 1, c % 3 == 0 ? 0.0 : 0.4);
  Eigen::VectorXd rows(k.rows());
  for (int i = 0; i < rows.size(); ++i) rows[i] = rng.uniform(-3, 3);
  // rows → pairs → rows is the identity (every row belongs to one contact).
  EXPECT_EQ(k.scatter(k.gather(rows)), rows);
  // pairs → rows → pairs keeps λ_n and keeps λ_t exactly where a tangent row exists.
  std::vector<double> pairs(2 * static_cast<size_t>(k.size()));
  for (double& v : pairs) v = rng.uniform(-3, 3);
  const std::vector<double> back = k.gather(k.scatter(pairs));
  std::vector<double> ln, lt;
  for (int c = 0; c < k.size(); ++c) {
    const auto u = static_cast<size_t>(c);
    EXPECT_EQ(back[2 * u], pairs[2 * u]) << c;
    EXPECT_EQ(back[2 * u + 1], k[c].has_friction() ? pairs[2 * u + 1] : 0.0) << c;
    EXPECT_EQ(k.lambda_n(rows, c), rows[k[c].normal_row]);
    EXPECT_EQ(k.lambda_t(rows, c), k[c].has_friction() ? rows[k[c].tangent_row] : 0.0);
    ln.push_back(pairs[2 * u]);
    lt.push_back(pairs[2 * u + 1]);
  }
  EXPECT_EQ(k.scatter(ln, lt), k.scatter(pairs));
  EXPECT_THROW((void)k.scatter(std::vector<double>(3)), InvalidArgument);
  EXPECT_THROW((void)k.scatter(ln, std::vector<double>(2)), InvalidArgument);
  EXPECT_THROW((void)k.gather(Eigen::VectorXd::Zero(k.rows() + 1)), InvalidArgument);
}

// A pair may own several points: the key is (pair, feature), and warm-start matching keeps
// them apart.
TEST(ContactConstraints, FeatureIdSeparatesPointsOfOnePair) {
  const ContactKey p0 = ContactKey::pair(2, 1), p1 = ContactKey::pair(1, 2, 1);
  EXPECT_EQ(p0, (ContactKey{1, 2, 0}));
  EXPECT_LT(p0, p1);
  EXPECT_LT(p1, ContactKey::pair(1, 3));
  EXPECT_NE(ContactKeyHash{}(p0), ContactKeyHash{}(p1));
  std::vector<Contact> prev(2), cur(3);
  prev[0].key = p0;
  prev[1].key = p1;
  cur[0].key = ContactKey::wall(Wall::Left, 1);
  cur[1].key = p1;
  cur[2].key = p0;
  std::swap(cur[1], cur[2]);  // key order: wall, (1,2,0), (1,2,1)
  EXPECT_EQ(match_contacts_by_key(prev, cur), (std::vector<int>{-1, 0, 1}));
  ContactConstraints k;
  k.add(1, 2, 0.5, 0);
  k.add(1, 2, 0.5, 1);
  EXPECT_EQ(k[1].feature, 1);
  EXPECT_EQ(k[1].normal_row, 2);
}

// Contacts with μ = 0 (normal kernel) between contacts with friction (contact blocks): the
// matrix-free PGS must follow pgs-assembled, also without A formed.
TEST(ContactConstraints, MatrixFreePgsWithMixedFrictionMatchesAssembled) {
  for (uint64_t seed = 31; seed <= 33; ++seed) {
    test::TestRng rng(seed);
    const LcpProblem p = test::random_contact(30, 60, true, rng, 0.5, 3);
    ASSERT_NO_THROW(p.validate());
    int frictionless = 0;
    for (const ContactConstraint& k : p.constraints) frictionless += !k.has_friction();
    ASSERT_EQ(frictionless, 20);
    LcpProblem matrix_free = p;
    matrix_free.A = SparseRowMatrix();
    ASSERT_FALSE(matrix_free.has_assembled_matrix());
    ASSERT_NO_THROW(matrix_free.validate());
    for (int k : {1, 10, 100}) {
      const SolveResult mf = run("pgs", p, k), as = run("pgs-assembled", p, k);
      EXPECT_LE(max_abs(mf.lambda - as.lambda), 1e-10 * std::max(1.0, max_abs(as.lambda))) << "seed " << seed << " k " << k;
      const SolveResult no_a = run("pgs", matrix_free, k);
      EXPECT_EQ(no_a.lambda, mf.lambda) << "A must not matter to pgs";
      // An assembled solver given no A forms it for that solve (same iterates to round-off:
      // the helper formed its A with another product order).
      EXPECT_LE(max_abs(run("pgs-assembled", matrix_free, k).lambda - as.lambda), 1e-10 * std::max(1.0, max_abs(as.lambda)));
      // The residual through J equals the one through A to round-off.
      EXPECT_NEAR(no_a.residual, natural_residual(test::without_jacobian(p), mf.lambda), 1e-9 * std::max(1.0, mf.residual));
    }
  }
}

TEST(ContactConstraints, ValidateRejectsConstraintsThatDisagreeWithTheRows) {
  test::TestRng rng(5);
  const LcpProblem p = test::random_contact(10, 8, true, rng);
  ASSERT_NO_THROW(p.validate());
  LcpProblem q = p;
  q.mu[q.constraints[2].tangent_row] = 0.9;  // row μ differs from the contact's
  EXPECT_THROW(q.validate(), InvalidArgument);
  q = p;
  q.constraints.add(0, 1, 0.0);  // owns a row the problem does not have
  EXPECT_THROW(q.validate(), InvalidArgument);
  q = p;
  q.constraints.clear();  // no structure at all is fine (pgs: general rows)
  EXPECT_NO_THROW(q.validate());
  EXPECT_LE(max_abs(run("pgs", q, 20).lambda - run("pgs", p, 20).lambda), 1e-10 * std::max(1.0, max_abs(run("pgs", p, 20).lambda)));
}

TEST(ContactConstraints, WorldAssemblesOneEntryPerContact) {
  for (const double mu : {0.5, 0.0}) {
    WorldDef d;
    d.contact.friction = mu;
    World w = stepped(d, "pgs", 120, 30);
    w.collide();
    const LcpProblem& p = w.assemble();
    EXPECT_FALSE(p.has_assembled_matrix());
    const ContactConstraints& k = w.constraints();
    ASSERT_EQ(k.size(), static_cast<int>(w.contacts().size()));
    ASSERT_GT(k.size(), 20);
    EXPECT_EQ(k.rows(), p.rows());
    for (int c = 0; c < k.size(); ++c) {
      const Contact& ct = w.contacts()[static_cast<size_t>(c)];
      EXPECT_EQ(k[c].body_a, ct.body_a >= 0 ? ct.body_a : -1);
      EXPECT_EQ(k[c].body_b, ct.body_b);
      EXPECT_EQ(k[c].mu, mu);
      EXPECT_EQ(k[c].has_friction(), mu > 0);
      if (mu > 0) { EXPECT_EQ(k[c].tangent_row, k[c].normal_row + 1); }
    }
    // A formed on demand equals J M⁻¹ Jᵀ Δt, and the residual through J agrees with it.
    LcpProblem with_a = p;
    with_a.ensure_assembled_matrix();
    ASSERT_TRUE(with_a.has_assembled_matrix());
    const Eigen::MatrixXd J(p.J);
    const Eigen::MatrixXd A = J * p.inv_mass.asDiagonal() * J.transpose() * p.dt;
    EXPECT_LE((Eigen::MatrixXd(with_a.A) - A).cwiseAbs().maxCoeff(), 1e-12 * A.cwiseAbs().maxCoeff());
    Eigen::VectorXd l(p.rows());
    test::TestRng rng(9);
    for (int i = 0; i < l.size(); ++i) l[i] = rng.uniform(0, 20);
    const Eigen::VectorXd w_a = with_a.A * l + with_a.b;
    EXPECT_LE(max_abs(lcp_velocity(p, l) - w_a), 1e-12 * std::max(1.0, max_abs(w_a)));
  }
}

TEST(ContactConstraints, StepWithAnAssembledSolverFormsA) {
  EXPECT_TRUE(make_solver("pgs-assembled")->needs_assembled_matrix());
  EXPECT_FALSE(make_solver("pgs")->needs_assembled_matrix());
  const World w = stepped(WorldDef{}, "pgs-assembled", 120, 20);
  ASSERT_GT(w.problem().rows(), 0);
  EXPECT_TRUE(w.problem().has_assembled_matrix());
}

// predict(λ) says what integrate(λ) does: the same state bit for bit, the energies of it,
// and the gaps the narrow phase measures at the new positions.
TEST(ContactConstraints, PredictIsIntegrate) {
  World w{WorldDef{}};
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 50;
  StepOutcome out;
  for (int s = 0; s < 160; ++s) {
    w.collide();
    w.assemble();
    const SolveResult r = solver->solve(w.problem(), Eigen::VectorXd(), o);
    w.predict(r.lambda, out);
    const std::vector<Contact> contacts = w.contacts();
    w.integrate(r.lambda);
    ASSERT_EQ(state_hash(out.bodies), state_hash(w.bodies())) << "step " << s;
    EXPECT_EQ(out.energy(), w.kinetic_energy() + w.potential_energy());
    ASSERT_EQ(out.gap.size(), contacts.size());
    double min_gap = 0;
    for (std::size_t c = 0; c < contacts.size(); ++c) {
      EXPECT_EQ(out.gap[c], contact_gap(w.bodies(), contacts[c], w.def().world.width, w.def().world.height));
      min_gap = std::min(min_gap, out.gap[c]);
    }
    EXPECT_EQ(out.max_penetration(), -min_gap);
  }
  // The narrow phase, run on the new state, measures the same gaps for the same pairs.
  const std::vector<Contact> before = w.previous_contacts();
  w.collide();
  int same = 0;
  const std::vector<int> match = match_contacts_by_key(before, w.contacts());
  for (std::size_t c = 0; c < match.size(); ++c) {
    if (match[c] < 0) continue;
    ++same;
    EXPECT_EQ(w.contacts()[c].gap,
              contact_gap(w.bodies(), before[static_cast<size_t>(match[c])], w.def().world.width, w.def().world.height));
  }
  EXPECT_GT(same, 20);
}

// The single merge pass of the builtin warm start visits exactly the matches of
// match_contacts_by_key, in contact order, and rejects an unsorted list as it does.
TEST(ContactMatch, ForEachMatchedContactVisitsTheMatchesOfMatchContactsByKey) {
  const auto contacts = [](std::initializer_list<ContactKey> keys) {
    std::vector<Contact> out;
    for (const ContactKey& k : keys) {
      Contact c;
      c.key = k;
      c.lambda_n = static_cast<double>(out.size());
      out.push_back(c);
    }
    return out;
  };
  const std::vector<Contact> prev = contacts({ContactKey::wall(Wall::Top, 0), ContactKey::wall(Wall::Left, 0),
                                              ContactKey::pair(0, 1), ContactKey::pair(1, 2), ContactKey::pair(1, 2, 1),
                                              ContactKey::pair(3, 4)});
  const std::vector<Contact> cur = contacts({ContactKey::wall(Wall::Left, 0), ContactKey::pair(1, 2, 1),
                                             ContactKey::pair(2, 3), ContactKey::pair(3, 4), ContactKey::pair(5, 6)});
  const std::vector<int> match = match_contacts_by_key(prev, cur);
  EXPECT_EQ(match, (std::vector<int>{1, 4, -1, 5, -1}));
  std::vector<int> visited(cur.size(), -1);
  std::size_t last = 0;
  bool ascending = true;
  for_each_matched_contact(prev, cur, [&](std::size_t c, const Contact& p) {
    ascending = ascending && c >= last;
    last = c;
    visited[c] = static_cast<int>(p.lambda_n);  // prev[j].lambda_n = j
  });
  EXPECT_TRUE(ascending);
  EXPECT_EQ(visited, match);
  const std::vector<Contact> unsorted = contacts({ContactKey::pair(3, 4), ContactKey::pair(0, 1)});
  const auto nothing = [](std::size_t, const Contact&) {};
  EXPECT_THROW(for_each_matched_contact(unsorted, cur, nothing), InvalidArgument);
  EXPECT_THROW(for_each_matched_contact(prev, unsorted, nothing), InvalidArgument);
}

}  // namespace
}  // namespace dc
