// Trainer: over-fitting a handful of samples, bit-exact determinism, the split by
// simulation, standardisation from the training split only, optimiser and schedules.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "dc/core/error.hpp"
#include "dc/learning/lr_schedule.hpp"
#include "dc/learning/optimizer.hpp"
#include "dc/learning/trainer.hpp"
#include "grad_check.hpp"

namespace dc {
namespace {

using test::fill_gaussian;

// Smooth random fields (so the labels are a learnable local function of the features):
// label0 = f0·f1 + 0.5·shift(f0), label1 = relu(f1) − f0.
std::vector<TrainingSample> make_data(int n, int cin, int cout, int size, int sims, bool weighted, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<TrainingSample> data;
  for (int k = 0; k < n; ++k) {
    TrainingSample s;
    s.features = Tensor(1, cin, size, size);
    fill_gaussian(s.features, rng);
    s.labels = Tensor(1, cout, size, size);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const float f0 = s.features(0, 0, y, x), f1 = s.features(0, 1 % cin, y, x);
        const float sh = s.features(0, 0, y, (x + 1) % size);
        s.labels(0, 0, y, x) = 3.0f + f0 * f1 + 0.5f * sh;
        if (cout > 1) s.labels(0, 1, y, x) = std::max(f1, 0.0f) - f0;
      }
    if (weighted) {
      s.weights = Tensor(1, 1, size, size);
      for (std::size_t i = 0; i < s.weights.size(); ++i) s.weights[i] = static_cast<float>(rng.uniform(0.5, 2.0));
    }
    s.simulation = k % sims;
    data.push_back(std::move(s));
  }
  return data;
}

/// A size × size grid (d = 0.5) reading the first `cin` feature channels; `cout` unnamed
/// output channels.
ModelGrid grid_for(int size, int cin, int cout) {
  ModelGrid g;
  g.image = FeatureImageDef::for_box(0.5 * (size - 1), 0.5 * (size - 1));
  const auto all = residual_feature_channels();
  g.image.channels.assign(all.begin(), all.begin() + cin);
  g.label_channels.clear();
  (void)cout;
  return g;
}

TEST(Trainer, TinyNetworkOverfitsAHandfulOfSamples) {
  const ArchSpec arch = ArchSpec::parse(R"(
name = "tiny"
[[layer]]
type = "conv"
out = 16
relu = true
[[layer]]
type = "conv"
out = 16
relu = true
[[layer]]
type = "conv"
out = 1
)");
  auto data = make_data(4, 2, 1, 8, 1, false, 7);
  for (TrainingSample& s : data) fill_gaussian(s.labels, *std::make_unique<Rng>(s.features.size() + 3));
  Model model(arch, grid_for(8, 2, 1), 2);
  TrainDef def;
  def.epochs = 3000;
  def.batch_size = 4;
  def.learning_rate = 0.02;
  def.momentum = 0.9;
  def.weight_decay = 0.0;
  def.validation_fraction = 0.0;
  def.seed = 3;
  double first = 0.0, best = 1e300;
  Trainer(def).train(model, data, [&](const EpochReport& r) {
    if (r.epoch == 0) first = r.train_loss;
    best = std::min(best, r.train_loss);
    return best > 1e-5 * first;  // stop once clearly below the bar
  });
  EXPECT_GT(first, 0.1);
  EXPECT_LT(best, 1e-4 * first) << "initial " << first << " best " << best;
}

TEST(Trainer, SameSeedAndThreadsGiveBitEqualTrainings) {
  // The default U-Net (with dropout) on 21×21, weighted loss, 4 simulations.
  const auto data = make_data(12, 4, 2, 21, 4, true, 11);
  TrainDef def;
  def.epochs = 3;
  def.batch_size = 4;
  def.seed = 99;
  def.schedule = "cosine";
  auto run = [&](std::vector<float>& weights) {
    Model model(default_arch(), grid_for(21, 4, 2), 4);
    const TrainResult r = Trainer(def).train(model, data);
    for (const ParamRef& p : model.network().parameters())
      weights.insert(weights.end(), p.value->data(), p.value->data() + p.value->size());
    return r;
  };
  std::vector<float> w1, w2;
  const TrainResult a = run(w1), b = run(w2);
  ASSERT_EQ(a.history.size(), 3u);
  ASSERT_EQ(w1.size(), w2.size());
  EXPECT_EQ(std::memcmp(w1.data(), w2.data(), sizeof(float) * w1.size()), 0);
  for (std::size_t e = 0; e < a.history.size(); ++e) {
    EXPECT_EQ(a.history[e].train_loss, b.history[e].train_loss);
    EXPECT_EQ(a.history[e].validation_loss, b.history[e].validation_loss);
    EXPECT_TRUE(std::isfinite(a.history[e].validation_loss));
  }
  EXPECT_EQ(a.validation_simulations.size(), 1u);  // ⌊0.2·4 + ½⌋ = 1
  EXPECT_EQ(a.train_simulations.size(), 3u);
  // A different seed gives a different run.
  def.seed = 100;
  std::vector<float> w3;
  run(w3);
  EXPECT_NE(std::memcmp(w1.data(), w3.data(), sizeof(float) * w1.size()), 0);
}

TEST(Trainer, StandardisesWithTrainingSplitOnlyAndSplitsBySimulation) {
  auto data = make_data(10, 2, 1, 6, 5, false, 5);
  // Make the validation simulation's features wildly different: the stats must not see it.
  Rng rng(1);
  const auto val = Trainer::pick_validation_simulations(data, 0.2, rng);
  ASSERT_EQ(val.size(), 1u);
  for (TrainingSample& s : data)
    if (s.simulation == val[0]) s.features.flat().array() += 1000.0f;
  const ArchSpec arch = ArchSpec::parse("[[layer]]\ntype = \"conv\"\nout = 1\n");
  Model model(arch, grid_for(6, 2, 1), 2);
  TrainDef def;
  def.epochs = 1;
  def.seed = 1;  // the trainer's first draw is the split, as above
  const TrainResult r = Trainer(def).train(model, data);
  EXPECT_EQ(r.validation_simulations, val);
  for (int sim : r.train_simulations) EXPECT_NE(sim, val[0]);
  EXPECT_LT(std::abs(model.input_stats.mean[0]), 1.0f);
  // One simulation only: no validation split, loss NaN.
  for (TrainingSample& s : data) s.simulation = 0;
  const TrainResult one = Trainer(def).train(model, data);
  EXPECT_TRUE(one.validation_simulations.empty());
  EXPECT_TRUE(std::isnan(one.history[0].validation_loss));
}

TEST(Trainer, RejectsBadDefsAndShapes) {
  TrainDef def;
  def.epochs = 0;
  EXPECT_THROW(Trainer{def}, ConfigError);
  def = {};
  def.schedule = "linear";
  EXPECT_THROW(Trainer{def}, ConfigError);
  def = {};
  def.init = "zeros";
  EXPECT_THROW(Trainer{def}, ConfigError);
  auto data = make_data(2, 2, 1, 6, 2, false, 5);
  Model model(ArchSpec::parse("[[layer]]\ntype = \"conv\"\nout = 1\n"), grid_for(7, 2, 1), 2);
  EXPECT_THROW(Trainer(TrainDef{}).train(model, data), InvalidArgument);
}

TEST(Optimizer, SgdMomentumAndWeightDecayFollowTheFormula) {
  Tensor w(1, 1, 1, 2), g(1, 1, 1, 2), b(1, 1, 1, 1), gb(1, 1, 1, 1);
  w[0] = 1.0f;
  w[1] = -2.0f;
  b[0] = 0.5f;
  std::vector<ParamRef> ps{{"w", &w, &g, true}, {"b", &b, &gb, false}};
  Sgd sgd(SgdDef{0.5, 0.1});
  g[0] = 0.2f;
  g[1] = 0.0f;
  gb[0] = 1.0f;
  sgd.step(ps, 0.1);
  // v = g + λw = (0.3, −0.2); w −= 0.1 v. Bias: no decay, v = 1.
  EXPECT_FLOAT_EQ(w[0], 1.0f - 0.03f);
  EXPECT_FLOAT_EQ(w[1], -2.0f + 0.02f);
  EXPECT_FLOAT_EQ(b[0], 0.4f);
  sgd.step(ps, 0.1);
  // v = 0.5·v + g + λw.
  const float v0 = 0.5f * 0.3f + 0.2f + 0.1f * 0.97f;
  EXPECT_NEAR(w[0], 0.97f - 0.1f * v0, 1e-6);
  EXPECT_NEAR(b[0], 0.4f - 0.1f * 1.5f, 1e-6);
  EXPECT_THROW(Sgd(SgdDef{1.0, 0.0}), InvalidArgument);
}

TEST(LrSchedule, ConstantStepCosine) {
  EXPECT_DOUBLE_EQ(ConstantLr(0.1).rate(50), 0.1);
  const StepLr step(0.1, 10, 0.5);
  EXPECT_DOUBLE_EQ(step.rate(9), 0.1);
  EXPECT_DOUBLE_EQ(step.rate(10), 0.05);
  EXPECT_DOUBLE_EQ(step.rate(25), 0.025);
  const CosineLr cos(0.1, 10, 0.0);
  EXPECT_DOUBLE_EQ(cos.rate(0), 0.1);
  EXPECT_NEAR(cos.rate(5), 0.05, 1e-15);
  EXPECT_NEAR(cos.rate(10), 0.0, 1e-15);
  EXPECT_NEAR(cos.rate(20), 0.0, 1e-15);
  EXPECT_THROW(make_lr_schedule("warmup", 0.1, 10), ConfigError);
}

}  // namespace
}  // namespace dc
