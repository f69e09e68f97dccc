// The field loss of training through PGS (PgsLoss::Field, pgs_trainer.hpp): J = 0 at builtin's
// G = 0, J at G* is log ε − log(‖G*‖² + ε), the gradient is the derivative, training lowers it,
// and validation reports what PGS pays (J_k of pgs-distance), not the field loss.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cnn/small_data_set.hpp"
#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/research/least_squares_field.hpp"
#include "dc/research/pgs_trainer.hpp"
#include "learning/small_archs.hpp"

namespace dc {
namespace {

DataSetParams field_params() {
  DataSetParams params = test::small_data_set_params(16.0, 80, 7, 30, 30);
  params.image.channels = parse_feature_channels("mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t");
  return params;
}

std::vector<PgsSample> field_samples(LabelKind kind, std::span<const int> sims) {
  return collect_pgs_samples(field_params(), sims, 10, {}, 0, kind);
}

TEST(PgsFieldLoss, IsZeroAtBuiltinMinimalAtTheFieldAndItsGradientIsTheDerivative) {
  const int sims[] = {0};
  for (const LabelKind kind : {LabelKind::Residual, LabelKind::Gain}) {
    const std::vector<PgsSample> samples = field_samples(kind, sims);
    ASSERT_FALSE(samples.empty());
    const PgsSample& s = *std::max_element(samples.begin(), samples.end(), [](const PgsSample& a, const PgsSample& b) {
      return a.problem.rows() < b.problem.rows();
    });
    ASSERT_GE(s.problem.rows(), 30);
    const double floor = 1e-2;
    PgsObjective obj(s, PgsLoss::Field, 7, floor, 50);
    const std::vector<float> field = least_squares_correction_grid(s, 50);
    const std::size_t n = field.size();
    // The entries a contact reads (Rᵀ1 ≠ 0): the loss's support, and ε = (their count)·f².
    std::vector<float> seen(n, 0.0f);
    s.readback.adjoint(std::vector<double>(2 * static_cast<std::size_t>(s.readback.points()), 1.0), seen.data());
    double f2 = 0, eps = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (seen[i] != 0.0f) {
        f2 += double(field[i]) * field[i];
        eps += floor * floor;
      }
    ASSERT_GT(f2, 0.0);
    EXPECT_DOUBLE_EQ(obj.builtin_loss(), f2);
    std::vector<float> zero(n, 0.0f);
    EXPECT_NEAR(obj.evaluate(zero.data(), nullptr), 0.0, 1e-12);
    EXPECT_NEAR(obj.evaluate(field.data(), nullptr), std::log(eps) - std::log(f2 + eps), 1e-9) << to_string(kind);
    // Half-way is in between.
    std::vector<float> half(n);
    for (std::size_t i = 0; i < n; ++i) half[i] = 0.5f * field[i];
    const double jh = obj.evaluate(half.data(), nullptr);
    EXPECT_LT(jh, 0.0);
    EXPECT_GT(jh, std::log(eps) - std::log(f2 + eps));
    // The gradient at a random G against central differences, on entries a contact reads and
    // on some it does not read (gradient 0: they never reach PGS).
    Rng rng(9);
    std::vector<float> G(n), dG(n, 0.0f);
    for (std::size_t i = 0; i < n; ++i) G[i] = field[i] + static_cast<float>(0.3 * (rng.uniform() * 2 - 1));
    (void)obj.evaluate(G.data(), dG.data());
    std::vector<std::size_t> at;
    for (std::size_t i = 0; i < n && at.size() < 6; i += 7)
      if (seen[i] != 0.0f) at.push_back(i);
    for (std::size_t i = 0; i < n && at.size() < 10; i += 97)
      if (seen[i] == 0.0f) {
        at.push_back(i);
        EXPECT_EQ(field[i], 0.0f) << i;
        EXPECT_EQ(dG[i], 0.0f) << i;
      }
    ASSERT_EQ(at.size(), 10u);
    for (const std::size_t i : at) {
      const float h = 1e-2f, g0 = G[i];
      G[i] = g0 + h;
      const double jp = obj.evaluate(G.data(), nullptr);
      G[i] = g0 - h;
      const double jm = obj.evaluate(G.data(), nullptr);
      G[i] = g0;
      const double num = (jp - jm) / (2.0 * double(h));
      EXPECT_NEAR(dG[i], num, 1e-2 * std::abs(num) + 1e-7) << to_string(kind) << " entry " << i;
    }
  }
}

/// Mean field-loss J over samples[idx] of `model`'s predictions.
double mean_field_objective(Model& model, std::span<const PgsSample> samples, const std::vector<std::size_t>& idx) {
  double sum = 0;
  for (const std::size_t i : idx) {
    const Tensor G = model.predict(samples[i].features);
    PgsObjective obj(samples[i], PgsLoss::Field, 1, 1e-2, 100);
    sum += obj.evaluate(G.data(), nullptr);
  }
  return sum / static_cast<double>(idx.size());
}

Model zero_head_gain_model(std::span<const PgsSample> samples) {
  ModelGrid grid;
  grid.image = field_params().image;
  grid.labels.kind = LabelKind::Gain;
  grid.labels.scale = 0.0;
  Model model(test::fast_head_arch(false), grid, samples[0].features.c());
  std::vector<const Tensor*> xs;
  for (const PgsSample& s : samples) xs.push_back(&s.features);
  model.input_stats = ChannelStats::compute(xs);  // standardised inputs, as train gives its models
  for (ParamRef& p : model.network().parameters())
    if (p.name.rfind("out/", 0) == 0) p.value->fill(0.0f);  // G = 0: builtin's start
  return model;
}

/// The network fits one sample's G* (J well below builtin's 0) by SGD on the field loss.
TEST(PgsFieldLoss, TrainingFitsTheFieldOfASample) {
  const int sims[] = {0};
  const std::vector<PgsSample> all = field_samples(LabelKind::Gain, sims);
  const PgsSample& big = *std::max_element(all.begin(), all.end(), [](const PgsSample& a, const PgsSample& b) {
    return a.problem.rows() < b.problem.rows();
  });
  const std::vector<PgsSample> one{big};
  Model model = zero_head_gain_model(one);
  const std::vector<std::size_t> idx{0};
  EXPECT_NEAR(mean_field_objective(model, one, idx), 0.0, 1e-12);
  PgsTrainDef def;
  def.loss = PgsLoss::Field;
  def.epochs = 60;
  def.batch = 1;
  def.learning_rate = 1e-3;
  def.validation_fraction = 0;
  const std::vector<PgsEpochReport> reports = train_through_pgs(model, one, def);
  ASSERT_EQ(reports.size(), 60u);
  EXPECT_TRUE(std::isnan(reports.back().validation_objective));
  EXPECT_LT(mean_field_objective(model, one, idx), -1.0);
}

/// With the field loss, the epoch's validation objective is J_k of pgs-distance (what PGS
/// pays), not the field loss.
TEST(PgsFieldLoss, ValidationIsThePgsDistanceObjective) {
  const int sims[] = {0, 1, 2};
  const std::vector<PgsSample> samples = field_samples(LabelKind::Gain, sims);
  Model model = zero_head_gain_model(samples);
  PgsTrainDef def;
  def.loss = PgsLoss::Field;
  def.unroll = 5;
  def.epochs = 1;
  def.batch = 4;
  def.learning_rate = 2e-5;
  def.validation_fraction = 0.34;
  const std::vector<PgsEpochReport> reports = train_through_pgs(model, samples, def);
  ASSERT_EQ(reports.size(), 1u);
  const std::vector<int> val = pgs_validation_simulations(samples, def);
  ASSERT_FALSE(val.empty());
  std::vector<std::size_t> va;
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (std::find(val.begin(), val.end(), samples[i].simulation) != val.end()) va.push_back(i);
  PgsTrainDef dist = def;
  dist.loss = PgsLoss::Distance;
  const double expected = pgs_objective_mean(model, samples, va, dist).first;
  EXPECT_NE(expected, 0.0);  // the model moved off builtin
  EXPECT_EQ(reports.back().validation_objective, expected);
  EXPECT_NE(reports.back().validation_objective, mean_field_objective(model, samples, va));
  EXPECT_EQ(validation_loss(PgsLoss::Field), PgsLoss::Distance);
  EXPECT_EQ(parse_pgs_loss("pgs-field"), PgsLoss::Field);
  def.field_iterations = 0;
  EXPECT_THROW(def.validate(), ConfigError);
}

}  // namespace
}  // namespace dc
