// assemble_lcp by parallel jobs of contacts gives the problem of one thread, bit for bit, on
// 2, 3 and 8 threads: contacts in key order (wall contacts first: the jobs place each contact's
// rows without a counting run), a wall contact out of that order, a static body among the
// circles, and μ = 0 (both counted by a first run); a contact failing the checks throws the
// same error on every thread count. Storage reused from another problem (other contacts, μ,
// masses, or values a fresh assembly never leaves, such as −0.0) gives the bits of fresh storage.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "assembly/assembly.hpp"
#include "dc/core/error.hpp"
#include "bytes_equal.hpp"

namespace dc {
namespace {

constexpr int kBodies = 5000;  // several jobs on 2 threads and more

BodyState bodies(bool with_static) {
  BodyState s;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(0.0, 100.0), v(-1.0, 1.0);
  for (int k = 0; k < kBodies; ++k) {
    if (with_static && k == 7)
      s.add_shaped(make_circle(0.5), Motion::Static, {x(rng), x(rng)}, 1.0);
    else if (with_static)
      s.add_shaped(make_circle(0.5), Motion::Dynamic, {x(rng), x(rng)}, 1.0, {v(rng), v(rng)}, 0.0, v(rng));
    else
      s.add({x(rng), x(rng)}, 0.5, 1.0, {v(rng), v(rng)}, 0.0, v(rng));
  }
  return s;
}

/// Wall contacts of the first bodies, then pairs (k, k + 1..3) in key order.
std::vector<Contact> contacts_in_key_order() {
  std::vector<Contact> out;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto contact = [&](int a, int b) {
    Contact c;
    c.key = a < 0 ? ContactKey{a, b, 0} : ContactKey::pair(a, b);
    c.body_a = a;
    c.body_b = b;
    c.point = {50 + 10 * u(rng), 50 + 10 * u(rng)};
    const double t = 3.0 * u(rng);
    c.normal = {std::cos(t), std::sin(t)};
    c.gap = 0.01 * u(rng);
    return c;
  };
  for (int b = 0; b < 300; ++b) out.push_back(contact(b % 3 == 0 ? -3 : -1, b));
  for (int a = 0; a + 3 < kBodies; ++a)
    for (int d = 1; d <= 3; ++d)
      if ((a + d) % 4 != 0) out.push_back(contact(a, a + d));
  return out;
}

WorldDef def_with(double friction) {
  WorldDef def;
  def.contact.friction = friction;
  return def;
}

bool same(const LcpProblem& p, const LcpProblem& q) {
  auto eq = [](const auto* a, const auto* b, long n) { return test::bytes_equal(a, b, static_cast<size_t>(n)); };
  if (p.rows() != q.rows() || p.J.cols() != q.J.cols() || p.J.nonZeros() != q.J.nonZeros()) return false;
  if (p.constraints.size() != q.constraints.size() || p.constraints.rows() != q.constraints.rows()) return false;
  for (int c = 0; c < p.constraints.size(); ++c) {
    const ContactConstraint &a = p.constraints[c], &b = q.constraints[c];
    if (a.normal_row != b.normal_row || a.tangent_row != b.tangent_row || a.body_a != b.body_a ||
        a.body_b != b.body_b || a.feature != b.feature || !eq(&a.mu, &b.mu, 1))
      return false;
  }
  return eq(p.J.outerIndexPtr(), q.J.outerIndexPtr(), p.rows() + 1) &&
         eq(p.J.innerIndexPtr(), q.J.innerIndexPtr(), p.J.nonZeros()) &&
         eq(p.J.valuePtr(), q.J.valuePtr(), p.J.nonZeros()) && eq(p.b.data(), q.b.data(), p.rows()) &&
         eq(p.lo.data(), q.lo.data(), p.rows()) && eq(p.hi.data(), q.hi.data(), p.rows()) &&
         eq(p.mu.data(), q.mu.data(), p.rows()) && p.normal_row == q.normal_row &&
         eq(p.inv_mass.data(), q.inv_mass.data(), p.inv_mass.size()) && p.dt == q.dt;
}

void expect_same_on_every_thread_count(const BodyState& s, const std::vector<Contact>& contacts, const WorldDef& def,
                                       const std::string& what) {
  LcpProblem one;
  assemble_lcp(s, contacts, def, one, 1);
  ASSERT_GT(one.rows(), 0) << what;
  for (const int threads : {2, 3, 8}) {
    LcpProblem many;
    assemble_lcp(s, contacts, def, many, threads);
    EXPECT_TRUE(same(one, many)) << what << ", " << threads << " threads";
    assemble_lcp(s, contacts, def, many, threads);  // storage reused
    EXPECT_TRUE(same(one, many)) << what << ", " << threads << " threads, again";
  }
}

TEST(AssemblyJobs, ContactsInKeyOrderGiveTheBitsOfOneThread) {
  expect_same_on_every_thread_count(bodies(false), contacts_in_key_order(), def_with(0.5), "key order");
}

TEST(AssemblyJobs, FrictionlessContactsGiveTheBitsOfOneThread) {
  expect_same_on_every_thread_count(bodies(false), contacts_in_key_order(), def_with(0.0), "μ = 0");
}

TEST(AssemblyJobs, AWallContactOutOfKeyOrderGivesTheBitsOfOneThread) {
  std::vector<Contact> contacts = contacts_in_key_order();
  const size_t late = contacts.size() * 3 / 4;
  std::swap(contacts[5], contacts[late]);  // a wall contact among the pairs, a pair among the walls
  expect_same_on_every_thread_count(bodies(false), contacts, def_with(0.5), "wall out of order");
}

TEST(AssemblyJobs, AStaticBodyGivesTheBitsOfOneThread) {
  expect_same_on_every_thread_count(bodies(true), contacts_in_key_order(), def_with(0.5), "static body");
}

TEST(AssemblyJobs, StorageHoldingAnotherProblemGivesTheBitsOfFreshStorage) {
  // The assembly leaves a value in place when its bits are the ones due (bounds, μ, normal
  // rows, M⁻¹): whatever the storage held before, the problem is the one fresh storage gets.
  std::vector<Contact> fewer = contacts_in_key_order();
  fewer.erase(fewer.begin() + 400, fewer.begin() + 411);  // later rows shifted by 11 contacts
  const BodyState plain = bodies(false), with_static = bodies(true);
  struct Case {
    const BodyState* s;
    const std::vector<Contact>* contacts;
    double friction;
    bool poison;  // −0.0 (and a wrong normal row) in every kept bound, μ and M⁻¹ first
  };
  const std::vector<Contact> all = contacts_in_key_order();
  const Case cases[] = {{&plain, &all, 0.5, false},      {&with_static, &fewer, 0.3, false},
                        {&plain, &all, 0.0, false},      {&plain, &fewer, 0.5, false},
                        {&with_static, &fewer, 0.5, true}, {&plain, &all, 0.5, true}};
  for (const int threads : {1, 2}) {
    LcpProblem kept;
    int k = 0;
    for (const Case& c : cases) {
      if (c.poison) {
        kept.lo.setConstant(-0.0);
        kept.hi.setConstant(-0.0);
        kept.mu.setConstant(-0.0);
        kept.inv_mass.setConstant(-0.0);
        std::fill(kept.normal_row.begin(), kept.normal_row.end(), 0);
      }
      assemble_lcp(*c.s, *c.contacts, def_with(c.friction), kept, threads);
      LcpProblem fresh;
      assemble_lcp(*c.s, *c.contacts, def_with(c.friction), fresh, threads);
      EXPECT_TRUE(same(fresh, kept)) << "case " << k << ", " << threads << " threads";
      ++k;
    }
  }
}

TEST(AssemblyJobs, AnInvalidContactThrowsOnEveryThreadCount) {
  const BodyState s = bodies(false);
  std::vector<Contact> contacts = contacts_in_key_order();
  contacts[contacts.size() / 2].body_b = contacts[contacts.size() / 2].body_a;  // body_a = body_b
  for (const int threads : {1, 2, 3, 8}) {
    LcpProblem p;
    EXPECT_THROW(assemble_lcp(s, contacts, def_with(0.5), p, threads), InvalidArgument) << threads << " threads";
  }
}

}  // namespace
}  // namespace dc
