// The solved λ packed apart from the contacts (world/parts/contact_lambdas.hpp): World::step's
// builtin warm start reads them there and the contacts' own λ fields are written on first read.
// Checked, on circles, boxes, static and kinematic bodies, restitution, and contacts appearing
// and disappearing: a World stepped with WarmStart::PreviousLambda moves bit for bit as one
// stepped with the guess put_matched_lambda(previous_contacts(), contacts(), problem()) (the
// contacts' own fields) and as one whose contacts are read after every stage; contacts() and
// previous_contacts() hold the solved λ of the rows; World::builtin_guess_into equals
// put_matched_lambda on the public views, also between integrate() and collide().
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "dc/engine/matched_lambda.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace dc {
namespace {

bool bits_equal(double x, double y) { return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y); }

::testing::AssertionResult bits_equal(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  if (x.size() != y.size()) return ::testing::AssertionFailure() << "sizes " << x.size() << " / " << y.size();
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (!bits_equal(x[i], y[i])) return ::testing::AssertionFailure() << "entry " << i << ": " << x[i] << " / " << y[i];
  return ::testing::AssertionSuccess();
}

/// The scenes: a falling pile of circles (contacts appear), a box pile, mixed shapes with static
/// and kinematic bodies, a rotating drum and a hopper (contacts come and go), a bouncing pile.
std::vector<std::pair<std::string, WorldDef>> lambda_scenes() {
  const std::string dir = std::string(DC_SOURCE_DIR) + "/scenes/";
  WorldDef bouncy = stress::scaled_seed_pile(150);
  bouncy.contact.restitution = 0.5;
  WorldDef frictionless = stress::scaled_seed_pile(200);
  frictionless.contact.friction = 0.0;
  return {{"circles", stress::scaled_seed_pile(300)},
          {"frictionless", frictionless},
          {"box_pile", load_scene(dir + "box_pile.toml")},
          {"mixed", load_scene(dir + "mixed.toml")},
          {"drum", load_scene(dir + "drum.toml")},
          {"hopper", load_scene(dir + "hopper.toml")},
          {"restitution", bouncy}};
}

constexpr int kLambdaSteps = 150;  ///< the boxes and the hopper's bodies settle into contact

SolverOptions lambda_options() {
  SolverOptions o;
  o.max_sweeps = 10;
  return o;
}

TEST(ContactLambdas, StepsAsTheContactsOwnLambda) {
  for (const auto& [name, def] : lambda_scenes()) {
    SCOPED_TRACE(name);
    World packed(def), own(def), read(def);
    const auto solver = make_solver("pgs");
    const SolverOptions o = lambda_options();
    const World::InitialGuess from_contacts = [](const World& w) {
      Eigen::VectorXd out;
      put_matched_lambda(w.previous_contacts(), w.contacts(), w.problem(), out);
      return out;
    };
    int matched = 0;
    for (int k = 0; k < kLambdaSteps; ++k) {
      const StepReport a = packed.step(*solver, o, World::WarmStart::PreviousLambda);
      const StepReport b = own.step(*solver, o, from_contacts);
      // `read`: its stages one by one, its contacts read after each (their λ written at once).
      read.collide();
      (void)read.previous_contacts();
      read.assemble();
      Eigen::VectorXd guess;
      put_matched_lambda(read.previous_contacts(), read.contacts(), read.problem(), guess);
      const SolveResult c = solver->solve(read.problem(), guess, o);
      read.integrate(c.lambda);
      (void)read.contacts();
      ASSERT_TRUE(bits_equal(a.solve.lambda, b.solve.lambda)) << "step " << k;
      ASSERT_TRUE(bits_equal(a.solve.lambda, c.lambda)) << "step " << k;
      ASSERT_EQ(state_hash(packed.bodies()), state_hash(own.bodies())) << "step " << k;
      ASSERT_EQ(state_hash(packed.bodies()), state_hash(read.bodies())) << "step " << k;
      // The solved λ in the contacts, read after the step.
      const std::vector<Contact>& cs = packed.contacts();
      const ContactConstraints& cons = packed.constraints();
      ASSERT_EQ(cs.size(), static_cast<std::size_t>(cons.size()));
      for (int q = 0; q < cons.size(); ++q) {
        ASSERT_TRUE(bits_equal(cs[static_cast<std::size_t>(q)].lambda_n, cons.lambda_n(a.solve.lambda, q))) << q;
        ASSERT_TRUE(bits_equal(cs[static_cast<std::size_t>(q)].lambda_t, cons.lambda_t(a.solve.lambda, q))) << q;
        matched += cs[static_cast<std::size_t>(q)].lambda_n > 0;
      }
    }
    EXPECT_GT(matched, 0);
  }
}

TEST(ContactLambdas, PreviousContactsHoldTheSolvedLambda) {
  World w(stress::scaled_seed_pile(300));
  const auto solver = make_solver("pgs");
  int pushing = 0;
  for (int k = 0; k < kLambdaSteps; ++k) {
    const StepReport r = w.step(*solver, lambda_options(), World::WarmStart::PreviousLambda);
    const std::vector<double> n = [&] {  // the solved λ_n by contact, before anything reads the contacts
      std::vector<double> v;
      for (int q = 0; q < w.constraints().size(); ++q) v.push_back(w.constraints().lambda_n(r.solve.lambda, q));
      return v;
    }();
    if (k % 2 == 1) continue;  // every other step: previous_contacts() first read after the next collide()
    w.collide();
    const std::vector<Contact>& prev = w.previous_contacts();
    ASSERT_EQ(prev.size(), n.size());
    for (std::size_t q = 0; q < n.size(); ++q) {
      ASSERT_TRUE(bits_equal(prev[q].lambda_n, n[q])) << "step " << k << " contact " << q;
      pushing += n[q] > 0;
    }
    w.assemble();
    w.integrate(solver->solve(w.problem(), Eigen::VectorXd::Zero(w.problem().rows()), lambda_options()).lambda);
  }
  EXPECT_GT(pushing, 0);
}

TEST(ContactLambdas, BuiltinGuessIntoEqualsPutMatchedLambda) {
  for (const auto& [name, def] : lambda_scenes()) {
    SCOPED_TRACE(name);
    World w(def);
    const auto solver = make_solver("pgs");
    KeptVector into;
    Eigen::VectorXd expected;
    for (int k = 0; k < kLambdaSteps; ++k) {
      w.collide();
      w.assemble();
      w.builtin_guess_into(into);  // before any read of the contacts writes their λ
      const World copy = w;
      put_matched_lambda(copy.previous_contacts(), copy.contacts(), copy.problem(), expected);
      ASSERT_TRUE(bits_equal(Eigen::VectorXd(into), expected)) << "step " << k;
      w.integrate(solver->solve(w.problem(), Eigen::VectorXd(into), lambda_options()).lambda);
      // Between integrate() and collide() the solved contacts are the previous ones.
      w.builtin_guess_into(into);
      const World after = w;
      put_matched_lambda(after.previous_contacts(), after.contacts(), after.problem(), expected);
      ASSERT_TRUE(bits_equal(Eigen::VectorXd(into), expected)) << "step " << k << " after integrate";
    }
  }
}

}  // namespace
}  // namespace dc
