// The cnn / cnn-hybrid warm starters: a finite, feasible guess of the right size from a
// tiny random model on a tiny scene; the gather path reads the data-set builder's label
// grid of λ* back exactly as the `sph` starter does; the hybrid keeps builtin's values for
// persistent contacts; a fully convolutional model runs on any box; model selection and
// size-dependent networks on another grid fail with clear errors.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

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

namespace dc {
namespace {

using test::advance_to_contacts;
using test::constant_gain_model;
using test::tiny_model;
using test::tiny_scene;

namespace fs = std::filesystem;

void expect_feasible(const World& w, const Eigen::VectorXd& lam) {
  const LcpProblem& p = w.problem();
  ASSERT_EQ(lam.size(), p.rows());
  ASSERT_TRUE(lam.allFinite());
  for (int i = 0; i < p.rows(); ++i) {
    EXPECT_GE(lam[i], p.lower(i, lam) - 1e-12) << "row " << i;
    EXPECT_LE(lam[i], p.upper(i, lam) + 1e-12) << "row " << i;
  }
}

/// The cap of every row of a network's guess or correction (docs/learning.md "Bounded
/// guesses"): the weight of every body plus the force that stops the row's approach alone.
Eigen::VectorXd force_caps(const World& world) {
  LcpProblem p = world.problem();
  p.ensure_assembled_matrix();
  double weight = 0;
  for (const double m : world.bodies().mass) weight += m;
  weight *= length(world.def().world.gravity);
  Eigen::VectorXd cap(p.rows());
  for (int i = 0; i < p.rows(); ++i) cap[i] = weight + std::max(0.0, -p.b[i]) / p.A.coeff(i, i);
  return cap;
}

Eigen::VectorXd capped(Eigen::VectorXd v, const Eigen::VectorXd& cap) {
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = std::clamp(v[i], -cap[i], cap[i]);
  return v;
}

TEST(CnnWarmStarter, TinyModelGivesAFiniteFeasibleGuessOfTheRightSize) {
  World world(tiny_scene());
  advance_to_contacts(world);
  CnnWarmStarter cnn(tiny_model(), "cnn", false);
  const Eigen::VectorXd lam = cnn.initial_guess(StepView{world, nullptr});
  expect_feasible(world, lam);
  EXPECT_GT(lam.cwiseAbs().maxCoeff(), 0.0);  // the network's output reaches the contacts
  EXPECT_EQ(cnn.last_timing().calls, 1);
  EXPECT_GT(cnn.last_timing().inference_ms, 0.0);
  // Deterministic: the same state gives the same guess.
  EXPECT_EQ(cnn.initial_guess(StepView{world, nullptr}), lam);
}

// A residual model adds its read-back to builtin: with a network that predicts exactly 0
// the guess IS builtin's; with a non-zero output it differs from builtin by the read-back of
// the predicted grid (guess_from_labels), projected.
TEST(CnnWarmStarter, ResidualModelIsBuiltinPlusTheReadBack) {
  World world(tiny_scene());
  advance_to_contacts(world);
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{world, nullptr});
  ASSERT_GT(b.cwiseAbs().maxCoeff(), 0.0);

  Model zero = tiny_model(12.0, true);
  for (const ParamRef& p : zero.network().parameters()) p.value->flat().setZero();
  zero.output_stats.mean = {0.0f, 0.0f};
  CnnWarmStarter z(std::move(zero), "cnn", false);
  EXPECT_EQ(z.initial_guess(StepView{world, nullptr}), b);

  CnnWarmStarter r(tiny_model(12.0, true), "cnn", false);
  const Eigen::VectorXd g = r.initial_guess(StepView{world, nullptr});
  expect_feasible(world, g);
  // Rebuild the same prediction by hand: features (with the previous contacts) → predict.
  FeatureImageDef img = FeatureImageDef::for_box(12, 12);
  img.channels = residual_feature_channels();
  FeatureImageBuilder builder(img);
  Tensor f(1, builder.feature_channels(), builder.ny(), builder.nx());
  builder.features(world.bodies(), world.contacts(), world.previous_contacts(),
                   std::span<float>(f.data(), f.size()));
  const Tensor labels = r.model().predict(f);
  const Eigen::VectorXd cap = force_caps(world);
  Eigen::VectorXd want = b + capped(r.guess_from_labels(world, labels, false), cap);
  project_feasible(world.problem(), want);
  ASSERT_EQ(g.size(), want.size());
  for (int i = 0; i < g.size(); ++i) EXPECT_NEAR(g[i], want[i], 1e-9 * (1 + std::abs(want[i]))) << "row " << i;
  EXPECT_GT((g - b).cwiseAbs().maxCoeff(), 1e-6);  // the correction is not empty

  // The dead zone soft-thresholds every row's correction before it is added to builtin.
  const Eigen::VectorXd raw = capped(r.guess_from_labels(world, labels, false), cap);
  const double tau = 0.5 * raw.cwiseAbs().maxCoeff();
  Model dz = tiny_model(12.0, true);
  ModelGrid dg = dz.grid();
  dg.labels.deadzone = tau;
  Model dzm(dz.network().arch(), dg, dz.network().input_shape().c);
  const auto src = r.model().network().parameters(), dst = dzm.network().parameters();
  for (std::size_t i = 0; i < src.size(); ++i) *dst[i].value = *src[i].value;
  dzm.input_stats = r.model().input_stats;
  dzm.output_stats = r.model().output_stats;
  CnnWarmStarter d(std::move(dzm), "cnn", false);
  Eigen::VectorXd want_dz = b;
  for (int i = 0; i < raw.size(); ++i)
    want_dz[i] += raw[i] > tau ? raw[i] - tau : (raw[i] < -tau ? raw[i] + tau : 0.0);
  project_feasible(world.problem(), want_dz);
  const Eigen::VectorXd got_dz = d.initial_guess(StepView{world, nullptr});
  for (int i = 0; i < g.size(); ++i) EXPECT_NEAR(got_dz[i], want_dz[i], 1e-9 * (1 + std::abs(want_dz[i]))) << "row " << i;

  // A residual model without the lambda_prev channels cannot be built.
  ModelGrid bad = tiny_model(12.0, false).grid();
  bad.labels.kind = LabelKind::Residual;
  EXPECT_THROW(Model(ArchSpec::parse("name = \"x\"\n[[layer]]\ntype = \"conv\"\nout = 2\n"), bad, 5), ConfigError);
}

// A network whose output explodes (the S·sinh head extrapolating; docs/learning.md "Bounded
// guesses") cannot hand PGS an absurd guess: each normal row's correction stays within
// W + max(0, −b_i)/A_ii (W = the weight of every body), and NaN outputs fall back to builtin.
TEST(CnnWarmStarter, AnExplodingNetworkIsCappedToForcesTheSceneCanNeed) {
  World world(tiny_scene());
  advance_to_contacts(world);
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{world, nullptr});
  const LcpProblem& p = world.problem();
  const Eigen::VectorXd cap = force_caps(world);
  for (const float mean : {1e30f, -1e30f, std::numeric_limits<float>::infinity()}) {
    Model huge = tiny_model(12.0, true);
    huge.output_stats.mean = {mean, mean};
    CnnWarmStarter c(std::move(huge), "cnn", false);
    const Eigen::VectorXd g = c.initial_guess(StepView{world, nullptr});
    expect_feasible(world, g);
    for (int i = 0; i < p.rows(); ++i) {
      if (p.normal_row[static_cast<std::size_t>(i)] >= 0) continue;  // friction rows follow their normal row
      EXPECT_LE(std::abs(g[i] - b[i]), cap[i] * (1 + 1e-12)) << "row " << i << ", mean " << mean;
    }
  }
  Model nan = tiny_model(12.0, true);
  nan.output_stats.mean = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::quiet_NaN()};
  CnnWarmStarter n(std::move(nan), "cnn", false);
  EXPECT_EQ(n.initial_guess(StepView{world, nullptr}), b);
}

// A state that is not finite (a diverged simulation) is refused by the feature image with the
// feature, the point and the cause (the starter adds its own name and the step).
TEST(CnnWarmStarter, ANonFiniteStateNamesTheFeatureThePointAndTheCause) {
  FeatureImageBuilder builder(FeatureImageDef::for_box(12, 12));
  BodyState s;
  s.add({3.0, 3.0}, 1.0, 1.0, {1.0, 0.0}, 0.0, 0.0);
  s.add({6.0, 3.0}, 1.0, 1.0, {std::numeric_limits<double>::infinity(), 0.0}, 0.0, 0.0);
  std::vector<float> img(builder.feature_size());
  try {
    builder.features(s, {}, img);
    ADD_FAILURE() << "expected an InvalidArgument";
  } catch (const InvalidArgument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("body 1: vx = inf is not finite"), std::string::npos) << m;
    EXPECT_NE(m.find("the simulation has diverged"), std::string::npos) << m;
  }
}

// A gain model's guess is λ_prev (1 + ĝ): a zero network IS builtin (what train --gain starts
// from), a uniform gain scales builtin's normal and friction rows, new contacts (λp = 0) stay 0.
TEST(CnnWarmStarter, GainModelScalesBuiltinByTheReadBackGain) {
  World world(tiny_scene());
  advance_to_contacts(world);
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{world, nullptr});
  ASSERT_GT(b.cwiseAbs().maxCoeff(), 0.0);
  CnnWarmStarter zero(constant_gain_model(0.0f, 0.0f), "cnn", false);
  EXPECT_EQ(zero.initial_guess(StepView{world, nullptr}), b);

  CnnWarmStarter scaled(constant_gain_model(0.5f, -0.25f), "cnn", false);
  const Eigen::VectorXd g = scaled.initial_guess(StepView{world, nullptr});
  expect_feasible(world, g);
  const ContactConstraints& cons = world.constraints();
  int loaded = 0;
  for (int k = 0; k < static_cast<int>(world.contacts().size()); ++k) {
    EXPECT_NEAR(cons.lambda_n(g, k), 1.5 * cons.lambda_n(b, k), 1e-9 * (1 + cons.lambda_n(b, k))) << k;
    EXPECT_NEAR(cons.lambda_t(g, k), 0.75 * cons.lambda_t(b, k), 1e-9 * (1 + std::abs(cons.lambda_t(b, k)))) << k;
    loaded += cons.lambda_n(b, k) > 0;
  }
  EXPECT_GT(loaded, 0);
}

/// 12 circles near the floor of a W × H box (they touch within a few steps).
WorldDef floor_scene(double width, double height) {
  WorldDef d = tiny_scene();
  d.world.width = width;
  d.world.height = height;
  d.bodies.mean = {width / 2, 3.0};
  d.bodies.sigma = 1.5;
  return d;
}

/// A small fully convolutional U-Net like models/arch/unet-fast.toml (stride-2 encoder,
/// upsampling matched to the encoder, 1×1 per-node head on the upsampled decoder and the
/// input: the sparse forward_at path), random weights, for the residual channels on `image`.
Model unet_model(const FeatureImageDef& image) {
  ModelGrid g;
  g.image = image;
  g.label_channels = label_channel_names();
  g.labels.kind = LabelKind::Residual;
  Model m(test::fast_head_arch(/*head_relu=*/false), g, static_cast<int>(image.channels.size()));
  Rng rng(21);
  m.network().initialize(*make_initializer("he_normal"), rng);
  m.output_stats.mean = {0.5f, 0.0f};
  m.output_stats.std = {2.0f, 0.5f};
  return m;
}

/// `m`'s weights and statistics in a model built for the grid `image`.
Model same_weights_on(Model& m, const FeatureImageDef& image) {
  ModelGrid g = m.grid();
  g.image = image;
  Model out(m.network().arch(), g, m.network().input_shape().c);
  const auto src = m.network().parameters(), dst = out.network().parameters();
  for (std::size_t i = 0; i < src.size(); ++i) *dst[i].value = *src[i].value;
  out.input_stats = m.input_stats;
  out.output_stats = m.output_stats;
  return out;
}

// The network is fully convolutional: a model trained on the seed's 61 × 61 grid runs on a
// 20 × 120 box's 41 × 241 grid with its own weights — exactly what a model built for that
// grid with the same weights gives — and, back on its own box, gives bit for bit what it gave
// before it ran elsewhere (and what a starter that never left that box gives).
TEST(CnnWarmStarter, FullyConvolutionalModelRunsOnAnotherBoxWithTheSameWeights) {
  FeatureImageDef seed_img = FeatureImageDef::for_box(30.0, 30.0), tall_img = FeatureImageDef::for_box(20.0, 120.0);
  seed_img.channels = tall_img.channels = residual_feature_channels();
  ASSERT_EQ(FeatureImageBuilder(seed_img).nx(), 61);
  ASSERT_EQ(FeatureImageBuilder(tall_img).nx(), 41);
  ASSERT_EQ(FeatureImageBuilder(tall_img).ny(), 241);
  World seed(floor_scene(30.0, 30.0)), tall(floor_scene(20.0, 120.0));
  advance_to_contacts(seed);
  advance_to_contacts(tall);

  Model m = unet_model(seed_img);
  Model on_tall = same_weights_on(m, tall_img);
  CnnWarmStarter moving(unet_model(seed_img), "cnn", false), home(unet_model(seed_img), "cnn", false);
  CnnWarmStarter native(std::move(on_tall), "cnn", false);

  const Eigen::VectorXd seed_before = moving.initial_guess(StepView{seed, nullptr});
  const Eigen::VectorXd tall_guess = moving.initial_guess(StepView{tall, nullptr});
  expect_feasible(tall, tall_guess);
  EXPECT_EQ(tall_guess, native.initial_guess(StepView{tall, nullptr}));
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{tall, nullptr});
  EXPECT_GT((tall_guess - b).cwiseAbs().maxCoeff(), 1e-6);  // the network's correction reaches the contacts
  EXPECT_EQ(moving.model().network().input_shape().w, 41);
  EXPECT_EQ(moving.model().network().output_shape().h, 241);

  const Eigen::VectorXd seed_after = moving.initial_guess(StepView{seed, nullptr});
  EXPECT_EQ(seed_after, seed_before);
  EXPECT_EQ(seed_after, home.initial_guess(StepView{seed, nullptr}));
  EXPECT_EQ(moving.model().network().input_shape().w, 61);
}

// A network whose parameters depend on the grid size (a dense head) cannot run on another
// box: one ConfigError naming the starter, both grids and the layer.
TEST(CnnWarmStarter, SizeDependentNetworkIsRefusedOnAnotherBox) {
  FeatureImageDef img = FeatureImageDef::for_box(12.0, 12.0);
  img.channels = residual_feature_channels();
  ModelGrid g;
  g.image = img;
  g.labels.kind = LabelKind::Residual;
  const FeatureImageBuilder b(img);
  Model m(ArchSpec::parse(R"(
name = "dense-head"
[[layer]]
type = "conv"
out = 2
stride = 2
[[layer]]
type = "dense"
out = [2, 25, 25]
)"),
          g, b.feature_channels());
  CnnWarmStarter cnn(std::move(m), "cnn:dense.h5", false);
  World own(floor_scene(12.0, 12.0)), other(floor_scene(20.0, 12.0));
  advance_to_contacts(own);
  advance_to_contacts(other);
  EXPECT_NO_THROW((void)cnn.initial_guess(StepView{own, nullptr}));
  try {
    (void)cnn.initial_guess(StepView{other, nullptr});
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("cnn:dense.h5"), std::string::npos) << msg;
    EXPECT_NE(msg.find("25 x 25"), std::string::npos) << msg;
    EXPECT_NE(msg.find("41 x 25"), std::string::npos) << msg;
    EXPECT_NE(msg.find("weight"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  // It still runs on its own box afterwards.
  EXPECT_NO_THROW((void)cnn.initial_guess(StepView{own, nullptr}));
}

// The starter converts only the nodes its read-back reads (guess_from_output); that must be
// exactly the read-back of the whole predicted label grid, with label compression (s·sinh),
// over consecutive steps (the per-call node marks must not leak stale values).
TEST(CnnWarmStarter, ReadBackOfTheStencilNodesEqualsTheWholePredictedGrid) {
  World world(tiny_scene());
  advance_to_contacts(world);
  Model base = tiny_model(12.0, true);
  ModelGrid g = base.grid();
  g.labels.scale = 10.0;
  Model m(base.network().arch(), g, base.network().input_shape().c);
  Rng rng(5);
  m.network().initialize(*make_initializer("he_normal"), rng);
  // Small de-standardised outputs keep s·sinh finite (the raw features are not standardised).
  m.output_stats.mean = {0.2f, 0.0f};
  m.output_stats.std = {0.05f, 0.02f};
  CnnWarmStarter cnn(std::move(m), "cnn", false);
  FeatureImageDef img = g.image;
  FeatureImageBuilder builder(img);
  Tensor f(1, builder.feature_channels(), builder.ny(), builder.nx());
  for (int step = 0; step < 3; ++step) {
    builder.features(world.bodies(), world.contacts(), world.previous_contacts(),
                     std::span<float>(f.data(), f.size()));
    const Tensor labels = cnn.model().predict(f);
    // Unprojected: a residual model's corrections have either sign.
    const Eigen::VectorXd whole = cnn.guess_from_labels(world, labels, false);
    const Tensor y = cnn.model().network_output(f);
    const Eigen::VectorXd sparse = cnn.guess_from_output(world, y, false);
    ASSERT_TRUE(whole.allFinite());
    EXPECT_EQ(sparse, whole) << "step " << step;
    // With the builder's S of the contacts: the Shepard gather from the stencils listed for
    // the stencil nodes, not from the points.
    ASSERT_NE(builder.contact_weights(), nullptr);
    EXPECT_EQ(cnn.guess_from_output(world, y, false, builder.contact_weights()), whole) << "step " << step;
    EXPECT_GT(whole.cwiseAbs().maxCoeff(), 0.0);
    const Eigen::VectorXd star = solve_oracle(world.problem()).lambda;
    world.integrate(star);
    world.collide();
    world.assemble();
  }
}

TEST(CnnWarmStarter, HybridKeepsBuiltinForPersistentContacts) {
  World world(tiny_scene());
  advance_to_contacts(world);
  CnnWarmStarter hybrid(tiny_model(), "cnn-hybrid", true);
  CnnWarmStarter cnn(tiny_model(), "cnn", false);
  const Eigen::VectorXd h = hybrid.initial_guess(StepView{world, nullptr});
  const Eigen::VectorXd c = cnn.initial_guess(StepView{world, nullptr});
  const Eigen::VectorXd b = default_warm_starters().make("builtin")->initial_guess(StepView{world, nullptr});
  expect_feasible(world, h);
  const auto& cur = world.contacts();
  const auto& prev = world.previous_contacts();
  int persistent = 0;
  for (int k = 0; k < static_cast<int>(cur.size()); ++k) {
    const bool old = std::any_of(prev.begin(), prev.end(), [&](const Contact& p) { return p.key == cur[k].key; });
    persistent += old;
    // Persistent: builtin's value. New: the cnn's (the tangent may be re-projected onto the
    // hybrid's λ_n, which for a new contact is the cnn's λ_n too).
    EXPECT_EQ(h[world.normal_row(k)], old ? b[world.normal_row(k)] : c[world.normal_row(k)]) << "contact " << k;
  }
  EXPECT_GT(persistent, 0);
}

TEST(CnnWarmStarter, HybridSkipsTheNetworkWhenNoContactIsNew) {
  World world(tiny_scene());
  advance_to_contacts(world);
  // Run until a step whose contacts all persist.
  CnnWarmStarter hybrid(tiny_model(), "cnn-hybrid", true);
  auto builtin = default_warm_starters().make("builtin");
  for (int s = 0; s < 300; ++s) {
    const Eigen::VectorXd h = hybrid.initial_guess(StepView{world, nullptr});
    if (hybrid.last_timing().calls == 0 && !world.contacts().empty()) {
      EXPECT_EQ(h, builtin->initial_guess(StepView{world, nullptr}));
      return;
    }
    world.integrate(solve_oracle(world.problem()).lambda);
    world.collide();
    world.assemble();
  }
  FAIL() << "no step with only persistent contacts";
}

TEST(CnnWarmStarter, RegistrySelectsTheModelAndReportsErrors) {
  const fs::path dir = fs::temp_directory_path() / ("dc_cnn_ws_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Model m = tiny_model();
  save_model(m, dir / "tiny.h5");

  WarmStarterRegistry r = default_warm_starters();
  add_cnn_warm_starters(r, dir / "default-missing.h5");
  ASSERT_TRUE(r.contains("cnn"));
  ASSERT_TRUE(r.contains("cnn-hybrid"));
  // Default model missing → IoError naming it.
  try {
    (void)r.make("cnn");
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("default-missing.h5"), std::string::npos) << e.what();
  }
  // cnn:PATH and WarmStartEnv::model_path.
  World world(tiny_scene());
  advance_to_contacts(world);
  auto a = r.make("cnn:" + (dir / "tiny.h5").string());
  EXPECT_EQ(a->name(), "cnn:" + (dir / "tiny.h5").string());
  WarmStartEnv env;
  env.model_path = (dir / "tiny.h5").string();
  auto b = r.make("cnn", env);
  EXPECT_EQ(a->initial_guess(StepView{world, nullptr}), b->initial_guess(StepView{world, nullptr}));
  // A (fully convolutional) model for another grid (30 × 30 box → 61 × 61) runs on the
  // 12 × 12 scene's 25 × 25 grid (size-dependent networks: SizeDependentNetworkIsRefused…).
  Model big = tiny_model(30.0);
  save_model(big, dir / "big.h5");
  auto c = r.make("cnn:" + (dir / "big.h5").string());
  expect_feasible(world, c->initial_guess(StepView{world, nullptr}));
  // Not a model file → IoError.
  { std::ofstream(dir / "junk.h5") << "not hdf5"; }
  EXPECT_THROW((void)r.make("cnn:" + (dir / "junk.h5").string()), IoError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dc
