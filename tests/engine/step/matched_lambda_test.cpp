// The builtin warm start's put_matched_lambda against the passes written out, and the
// contact impulse against Eigen's product. Checked: put_matched_lambda equals a zero vector, the matched
// puts and project_feasible bit for bit (also with non-finite and out-of-bound previous λ), and
// throws as the match does on an unsorted list; integrate_bodies's impulse equals Eigen's
// Jᵀλ·Δt bit for bit, on the problem's rows and on rows whose columns are not in ascending order.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>

#include "dc/core/error.hpp"
#include "dc/engine/matched_lambda.hpp"
#include "dc/engine/step_outcome.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "engine/previous_lambda_by_key.hpp"

namespace dc {
namespace {

::testing::AssertionResult same_bits(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  if (x.size() != y.size()) return ::testing::AssertionFailure() << "sizes " << x.size() << " / " << y.size();
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (std::bit_cast<std::uint64_t>(x[i]) != std::bit_cast<std::uint64_t>(y[i]))
      return ::testing::AssertionFailure() << "entry " << i << ": " << x[i] << " / " << y[i];
  return ::testing::AssertionSuccess();
}

/// A pile of 300 bodies stepped 150 times: contacts that persist, new ones and some gone.
World stepped_pile() {
  World w(stress::scaled_seed_pile(300));
  const auto solver = make_solver("pgs");
  SolverOptions o;
  o.max_sweeps = 20;
  for (int k = 0; k < 150; ++k) w.step(*solver, o, World::WarmStart::PreviousLambda);
  w.collide();
  w.assemble();
  return w;
}

Eigen::VectorXd in_passes(const World& w) {
  Eigen::VectorXd out = test::previous_lambda_by_key(w);
  project_feasible(w.problem(), out);
  return out;
}

TEST(MatchedLambda, EqualsTheSeparatePasses) {
  const World w = stepped_pile();
  ASSERT_GT(w.contacts().size(), 100u);
  Eigen::VectorXd one_pass;
  put_matched_lambda(w.previous_contacts(), w.contacts(), w.problem(), one_pass);
  EXPECT_TRUE(same_bits(one_pass, in_passes(w)));
  // Previous λ outside the bounds or not finite: projected alike.
  std::vector<Contact> previous = w.previous_contacts();
  for (std::size_t c = 0; c < previous.size(); ++c) {
    if (c % 3 == 0) previous[c].lambda_n = -previous[c].lambda_n - 1.0;
    if (c % 5 == 0) previous[c].lambda_t = 1e9 * (c % 2 ? 1.0 : -1.0);
    if (c % 7 == 0) previous[c].lambda_n = std::numeric_limits<double>::quiet_NaN();
    if (c % 11 == 0) previous[c].lambda_t = std::numeric_limits<double>::infinity();
  }
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(w.problem().rows());
  const std::vector<int> match = match_contacts_by_key(previous, w.contacts());
  for (std::size_t c = 0; c < match.size(); ++c)
    if (match[c] >= 0) {
      const Contact& p = previous[static_cast<std::size_t>(match[c])];
      w.constraints().put(static_cast<int>(c), p.lambda_n, p.lambda_t, expected);
    }
  project_feasible(w.problem(), expected);
  put_matched_lambda(previous, w.contacts(), w.problem(), one_pass);
  EXPECT_TRUE(same_bits(one_pass, expected));
}

TEST(MatchedLambda, ThrowsOnUnsortedLists) {
  const World w = stepped_pile();
  std::vector<Contact> previous = w.previous_contacts();
  ASSERT_GT(previous.size(), 10u);
  std::swap(previous[3], previous[previous.size() - 4]);
  Eigen::VectorXd out;
  EXPECT_THROW(put_matched_lambda(previous, w.contacts(), w.problem(), out), InvalidArgument);
  std::vector<Contact> current = w.contacts();
  std::swap(current[2], current[current.size() - 3]);
  EXPECT_THROW(put_matched_lambda(w.previous_contacts(), current, w.problem(), out), InvalidArgument);
}

TEST(ContactImpulse, EqualsEigensProduct) {
  const World w = stepped_pile();
  LcpProblem p = w.problem();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 3.0);
  Eigen::VectorXd lambda(p.rows());
  for (Eigen::Index i = 0; i < lambda.size(); ++i) lambda[i] = u(rng);
  const double dt = w.def().time.dt;
  const auto impulse_of = [&](const LcpProblem& q) {
    BodyState s = w.bodies();
    Eigen::VectorXd impulse;
    integrate_bodies(q, lambda, w.def().world.gravity, dt, s, impulse);
    return impulse;
  };
  const Eigen::VectorXd eigen = p.J.transpose() * lambda * dt;
  EXPECT_TRUE(same_bits(impulse_of(p), eigen));
  // Some tangent rows' columns in another order than their normal row's.
  int turned = 0;
  for (int r = 1; r < p.rows(); r += 4) {
    if (p.normal_row[static_cast<std::size_t>(r)] < 0) continue;
    int* inner = p.J.innerIndexPtr() + p.J.outerIndexPtr()[r];
    double* value = p.J.valuePtr() + p.J.outerIndexPtr()[r];
    const int n = p.J.outerIndexPtr()[r + 1] - p.J.outerIndexPtr()[r];
    if (n < 6) continue;
    for (int k = 0; k < 3; ++k) {  // the two bodies' columns swapped (columns out of ascending order)
      std::swap(inner[k], inner[k + 3]);
      std::swap(value[k], value[k + 3]);
    }
    ++turned;
  }
  ASSERT_GT(turned, 10);
  EXPECT_TRUE(same_bits(impulse_of(p), Eigen::VectorXd(p.J.transpose() * lambda * dt)));
}

}  // namespace
}  // namespace dc
