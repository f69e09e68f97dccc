// The cnn starter's read-back against the grid oracles it approximates (sph, sph-gain):
// the same transfer gives the same numbers.
#include <gtest/gtest.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "cnn/tiny_cnn.hpp"
#include "dc/cnn/cnn_warm_starter.hpp"
#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/engine/contact.hpp"
#include "dc/engine/world.hpp"
#include "dc/learning/channel_stats.hpp"
#include "dc/learning/initializer.hpp"
#include "dc/learning/model_file.hpp"
#include "dc/sph/sph_transfer.hpp"
#include "dc/warmstart/oracle.hpp"
#include "learning/small_archs.hpp"
#include "research/research_registry.hpp"
#include "settled_pile.hpp"

namespace dc {
namespace {

using test::advance_to_contacts;
using test::constant_gain_model;
using test::tiny_model;
using test::tiny_scene;

TEST(CnnWarmStarter, GatherOfTheBuildersLabelGridEqualsTheSphStarter) {
  World world(tiny_scene());
  const Eigen::VectorXd star = advance_to_contacts(world);
  // The label image exactly as `deepcontact generate` writes it (float32 Shepard numerators).
  FeatureImageBuilder builder(FeatureImageDef::for_box(12.0, 12.0));
  const std::vector<double> nt = world.constraints().gather(star);
  Tensor labels(1, 2, builder.ny(), builder.nx());
  builder.labels(world.contacts(), nt, std::span<float>(labels.data(), labels.size()));

  CnnWarmStarter cnn(tiny_model(), "cnn", false);
  const Eigen::VectorXd from_grid = cnn.guess_from_labels(world, labels);
  const Eigen::VectorXd sph = test::research_registry().make("sph")->initial_guess(StepView{world, &star});
  ASSERT_EQ(from_grid.size(), sph.size());
  // Equal up to the float32 rounding of the stored grid.
  const double scale = std::max(1.0, star.cwiseAbs().maxCoeff());
  for (int i = 0; i < sph.size(); ++i) EXPECT_NEAR(from_grid[i], sph[i], 1e-6 * scale) << "row " << i;
  EXPECT_GT(sph.cwiseAbs().maxCoeff(), 0.0);
}

// The gain read-back of G = N/D (N = Σ W δ λp, D = Σ W λp², δ = λ* − λp) is the sph-gain
// oracle's ĝ: a gain model that predicted that field would reproduce sph-gain's guess.
TEST(CnnWarmStarter, GainReadBackOfTheOracleFieldIsTheSphGainGuess) {
  World world(tiny_scene());
  advance_to_contacts(world);
  // One more oracle step so that most contacts carry a history.
  world.integrate(solve_oracle(world.problem()).lambda);
  world.collide();
  world.assemble();
  const Eigen::VectorXd star = solve_oracle(world.problem()).lambda;
  const Eigen::VectorXd b = test::research_registry().make("builtin")->initial_guess(StepView{world, nullptr});
  CnnWarmStarter cnn(constant_gain_model(0.0f, 0.0f), "cnn", false);
  const ContactConstraints& cons = world.constraints();
  const std::size_t n = world.contacts().size();
  ASSERT_GE(n, 5u);
  // λp as the cnn reads it: the previous step's λ by contact key (builtin before projection).
  Eigen::VectorXd lp = Eigen::VectorXd::Zero(world.problem().rows());
  const std::vector<int> match = match_contacts_by_key(world.previous_contacts(), world.contacts());
  std::vector<Vec2> pts;
  std::vector<double> num(2 * n), den(2 * n);
  for (std::size_t c = 0; c < n; ++c) {
    const int k = static_cast<int>(c);
    pts.push_back(world.contacts()[c].point);
    if (match[c] >= 0) {
      const Contact& p = world.previous_contacts()[static_cast<std::size_t>(match[c])];
      cons.put(k, p.lambda_n, p.lambda_t, lp);
    }
    const double pn = cons.lambda_n(lp, k), pt = cons.lambda_t(lp, k);
    num[2 * c] = (cons.lambda_n(star, k) - pn) * pn;
    num[2 * c + 1] = (cons.lambda_t(star, k) - pt) * pt;
    den[2 * c] = pn * pn;
    den[2 * c + 1] = pt * pt;
  }
  SphTransferDef def = cnn.model().grid().image.sph;
  def.grid.channels = 2;
  def.normalisation = SphNormalisation::None;
  SphTransfer t(def);
  const std::span<const double> sN = t.splat(pts, num).data();
  const std::vector<double> N(sN.begin(), sN.end());
  const SphGrid& gD = t.splat(pts, den);
  const std::vector<double> D(gD.data().begin(), gD.data().end());
  Tensor field(1, 2, gD.ny(), gD.nx());
  ASSERT_EQ(field.size(), N.size());
  for (std::size_t i = 0; i < N.size(); ++i) field.data()[i] = D[i] > 0 ? static_cast<float>(N[i] / D[i]) : 0.0f;
  Eigen::VectorXd mine = lp + cnn.guess_from_labels(world, field, false);
  project_feasible(world.problem(), mine);
  const Eigen::VectorXd oracle = test::research_registry().make("sph-gain")->initial_guess(StepView{world, &star});
  ASSERT_EQ(mine.size(), oracle.size());
  const double scale = std::max(1.0, star.cwiseAbs().maxCoeff());
  for (int i = 0; i < mine.size(); ++i) EXPECT_NEAR(mine[i], oracle[i], 1e-6 * scale) << "row " << i;
  EXPECT_GT((oracle - b).cwiseAbs().maxCoeff(), 1e-3 * scale);  // the gain is not empty
}

TEST(FeatureImage, LabelGatheredAtTheContactsEqualsTheSphWarmStarter) {
  WorldDef def;
  def.bodies.count = 20;
  def.bodies.seed = 7;
  World world(def);
  test::step_then_assemble(world, 150, 200);  // the pile forms: many touching contacts
  const auto& contacts = world.contacts();
  ASSERT_GT(contacts.size(), 5u);
  const Eigen::VectorXd star = solve_oracle(world.problem()).lambda;

  FeatureImageBuilder b(FeatureImageDef::for_box(def.world.width, def.world.height));
  const std::vector<double> lambda = world.constraints().gather(star);
  std::vector<float> img(b.label_size());
  b.labels(contacts, lambda, img);

  // Label (float32) → grid → Shepard gather at the contact points.
  SphTransfer transfer(b.def().sph);
  SphGrid grid(b.def().sph.grid);
  ASSERT_EQ(grid.size(), img.size());
  for (std::size_t k = 0; k < img.size(); ++k) grid.data()[k] = img[k];
  std::vector<Vec2> points;
  for (const Contact& c : contacts) points.push_back(c.point);
  const auto back = transfer.gather(grid, points);
  Eigen::VectorXd ours = world.constraints().scatter(back);
  project_feasible(world.problem(), ours);

  auto sph = test::research_registry().make("sph");
  const Eigen::VectorXd theirs = sph->initial_guess(StepView{world, &star});
  ASSERT_EQ(ours.size(), theirs.size());
  const double scale = std::max(1.0, star.cwiseAbs().maxCoeff());
  for (int r = 0; r < ours.size(); ++r) EXPECT_NEAR(ours[r], theirs[r], 1e-5 * scale) << "row " << r;
}

}  // namespace
}  // namespace dc
