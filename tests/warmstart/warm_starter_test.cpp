// Unit tests of the warm-start layer (docs/design.md §4): builtin's key matching (persisting, new and
// vanished contacts) and the registry (unknown names, add()).
#include <gtest/gtest.h>

#include <cmath>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "warmstart/three_discs.hpp"

namespace dc {
namespace {

using test::three_discs;
using test::tight;
using test::three_discs_next_step;

TEST(BuiltinWarmStart, PersistingContactsGetTheirLambdaNewOnesZero) {
  World w = three_discs();
  const auto pgs = make_solver("pgs");
  w.step(*pgs, tight());
  ASSERT_EQ(w.contacts().size(), 2u);
  const Contact kept = w.contacts()[0], gone = w.contacts()[1];  // floor–0, floor–1
  ASSERT_EQ(kept.key, ContactKey::wall(Wall::Bottom, 0));
  ASSERT_GT(gone.lambda_n, kept.lambda_n);  // the larger disc is heavier
  ASSERT_NE(kept.lambda_t, 0.0);

  // Disc 1 jumps away (its contact vanishes), disc 2 lands (a new contact takes index 1).
  w.bodies().position[1] = {20.0, 60.0};
  w.bodies().position[2] = {30.0, 1.2};
  w.collide();
  const LcpProblem& p = w.assemble();
  ASSERT_EQ(w.contacts().size(), 2u);
  ASSERT_EQ(w.contacts()[1].key, ContactKey::wall(Wall::Bottom, 2));

  const auto builtin = default_warm_starters().make("builtin");
  const Eigen::VectorXd g = builtin->initial_guess(StepView{w});
  ASSERT_EQ(g.size(), p.rows());
  EXPECT_EQ(g[w.normal_row(0)], kept.lambda_n);
  EXPECT_EQ(g[w.tangent_row(0)], kept.lambda_t);
  EXPECT_EQ(g[w.normal_row(1)], 0.0);  // new: not the vanished contact's λ at the same index
  EXPECT_EQ(g[w.tangent_row(1)], 0.0);
}

TEST(BuiltinWarmStart, FirstStepIsZero) {
  World w = three_discs();
  w.collide();
  w.assemble();
  const auto builtin = default_warm_starters().make("builtin");
  EXPECT_EQ(builtin->initial_guess(StepView{w}).cwiseAbs().maxCoeff(), 0.0);
}

TEST(WarmStarterRegistry, UnknownNameListsTheValidOnes) {
  const WarmStarterRegistry r = default_warm_starters();
  for (const char* n : {"zero", "builtin", "sph-prev", "gate", "builtin-coarse"}) EXPECT_TRUE(r.contains(n)) << n;
  try {
    (void)r.make("nonesuch:3");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("nonesuch"), std::string::npos) << msg;
    for (const std::string& n : r.names()) EXPECT_NE(msg.find(n), std::string::npos) << n << ": " << msg;
  }
  EXPECT_THROW(r.make("builtin:1"), ConfigError);  // builtin takes no argument
}

TEST(WarmStarterRegistry, AddedFactoriesReceiveTheirArgumentAndEnv) {
  struct Constant final : WarmStarter {
    double value;
    explicit Constant(double v) : value(v) {}
    std::string name() const override { return "const:" + std::to_string(value); }
    Eigen::VectorXd initial_guess(const StepView& v) override {
      return Eigen::VectorXd::Constant(v.world.problem().rows(), value);
    }
  };
  WarmStarterRegistry r;
  std::uint64_t seen_seed = 0;
  r.add("const", "a constant guess", [&](const WarmStartSpec& s, const WarmStartEnv& env) {
    seen_seed = env.seed;
    return std::make_unique<Constant>(std::stod(s.arg));
  });
  EXPECT_EQ(r.names(), std::vector<std::string>{"const"});
  EXPECT_NE(r.help().find("a constant guess"), std::string::npos);
  WarmStartEnv env;
  env.seed = 77;
  World w = three_discs();
  w.collide();
  w.assemble();
  const Eigen::VectorXd g = r.make("const:2.5", env)->initial_guess(StepView{w});
  ASSERT_EQ(g.size(), w.problem().rows());
  ASSERT_GT(g.size(), 0);
  EXPECT_EQ(g[0], 2.5);
  EXPECT_EQ(seen_seed, 77u);
  EXPECT_THROW(r.add("a:b", "", [](const WarmStartSpec&, const WarmStartEnv&) { return std::unique_ptr<WarmStarter>(); }),
               InvalidArgument);
  EXPECT_THROW(r.add("nofactory", "", WarmStarterFactory{}), InvalidArgument);
  EXPECT_THROW(r.make(":x"), ConfigError);
}

}  // namespace
}  // namespace dc
