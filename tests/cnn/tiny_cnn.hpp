#pragma once
// Tiny scenes and random models for the cnn starter's tests (and the research tests that
// compare it with the grid oracles).
#include <Eigen/Core>
#include <gtest/gtest.h>

#include "dc/cnn/feature_image.hpp"
#include "dc/core/rng.hpp"
#include "dc/engine/world.hpp"
#include "dc/learning/channel_stats.hpp"
#include "dc/learning/initializer.hpp"
#include "dc/learning/model.hpp"
#include "dc/warmstart/oracle.hpp"
#include "learning/small_archs.hpp"

namespace dc::test {

/// 12 circles falling in a 12 × 12 box (25 × 25 grid at d = 0.5).
inline WorldDef tiny_scene(double box = 12.0) {
  WorldDef d;
  d.world.width = d.world.height = box;
  d.bodies.count = 12;
  d.bodies.mean = {box / 2, box / 2};
  d.bodies.sigma = 2.0;
  d.bodies.seed = 3;
  return d;
}

/// Steps `world` with the oracle until a step has ≥ 5 contacts and a previous step with
/// contacts; leaves it collided and assembled. Returns this step's λ*.
inline Eigen::VectorXd advance_to_contacts(World& world) {
  for (int s = 0; s < 400; ++s) {
    world.collide();
    const LcpProblem& p = world.assemble();
    const Eigen::VectorXd star = solve_oracle(p).lambda;
    if (world.contacts().size() >= 5 && !world.previous_contacts().empty()) return star;
    world.integrate(star);
  }
  ADD_FAILURE() << "no contacts within 400 steps";
  return {};
}

/// A tiny random model for the data set's default image setting on `box` (or the residual
/// model's channels and label kind).
inline Model tiny_model(double box = 12.0, bool residual = false) {
  FeatureImageDef img = FeatureImageDef::for_box(box, box);
  if (residual) img.channels = residual_feature_channels();
  const FeatureImageBuilder b(img);
  ModelGrid g;
  g.image = img;
  g.label_channels = label_channel_names();
  if (residual) g.labels.kind = LabelKind::Residual;
  Model m(ArchSpec::parse(R"(
name = "tiny"
[[layer]]
type = "conv"
out = 4
relu = true
[[layer]]
type = "conv"
out = 2
)"),
          g, b.feature_channels());
  Rng rng(11);
  m.network().initialize(*make_initializer("he_normal"), rng);
  // Output de-standardisation scaled up so the guesses are clearly non-zero.
  m.output_stats.mean = {5.0f, 0.0f};
  m.output_stats.std = {10.0f, 3.0f};
  return m;
}

/// tiny_model's residual network as a GAIN model (identity output, no compression) whose
/// every parameter is zero except the output layer's biases (gn, gt): a uniform gain field.
inline Model constant_gain_model(float gn, float gt) {
  Model r = tiny_model(12.0, true);
  ModelGrid g = r.grid();
  g.labels.kind = LabelKind::Gain;
  g.labels.scale = 0.0;
  Model m(r.network().arch(), g, r.network().input_shape().c);
  const std::string head = m.network().arch().layers.back().name + "/bias";
  for (const ParamRef& p : m.network().parameters()) {
    p.value->flat().setZero();
    if (p.name == head) {
      p.value->flat()[0] = gn;
      p.value->flat()[1] = gt;
    }
  }
  m.input_stats = r.input_stats;
  m.output_stats = ChannelStats::identity(2);
  return m;
}

}  // namespace dc::test
