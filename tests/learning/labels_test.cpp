// labels.hpp: the one definition of a model's labels — the training target (train) and its
// inverse (Model::predict + the cnn starter's read-back) undo each other.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/learning/labels.hpp"

namespace dc {
namespace {

Tensor random_tensor(int c, int h, int w, std::uint64_t seed, double scale) {
  Tensor t(1, c, h, w);
  Rng rng(seed);
  for (float& v : t.flat()) v = static_cast<float>(scale * rng.uniform(-1.0, 1.0));
  return t;
}

TEST(Labels, KindNamesRoundTripAndUnknownNamesAreOneLineErrors) {
  for (const LabelKind k : {LabelKind::Absolute, LabelKind::Residual}) EXPECT_EQ(parse_label_kind(to_string(k)), k);
  EXPECT_STREQ(to_string(LabelKind::Residual), "residual");
  try {
    (void)parse_label_kind("relative");
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("relative"), std::string::npos) << m;
    EXPECT_NE(m.find("absolute"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(Labels, DefinitionValidation) {
  EXPECT_NO_THROW(LabelDef{}.validate());
  EXPECT_THROW((LabelDef{LabelKind::Absolute, -1.0, 0.0}.validate()), ConfigError);
  EXPECT_THROW((LabelDef{LabelKind::Residual, 0.0, NAN}.validate()), ConfigError);
  EXPECT_THROW((LabelDef{LabelKind::Residual, INFINITY, 0.0}.validate()), ConfigError);
}

TEST(Labels, ResidualTargetIsLabelMinusLambdaPrevCompressed) {
  const std::vector<FeatureChannel> ch = residual_feature_channels();
  const auto [pn, pt] = lambda_prev_channels(ch, "test");
  EXPECT_EQ(ch[static_cast<std::size_t>(pn)], FeatureChannel::LambdaPrevN);
  EXPECT_EQ(ch[static_cast<std::size_t>(pt)], FeatureChannel::LambdaPrevT);
  const int H = 5, W = 7;
  const Tensor features = random_tensor(static_cast<int>(ch.size()), H, W, 1, 30.0);
  const Tensor raw = random_tensor(2, H, W, 2, 100.0);
  const LabelDef def{LabelKind::Residual, 8.0, 0.0};
  Tensor target = raw;
  training_labels(target, features, ch, def);
  const std::size_t P = static_cast<std::size_t>(H) * W;
  for (std::size_t q = 0; q < P; ++q) {
    const float dn = raw[q] - features[static_cast<std::size_t>(pn) * P + q];
    const float dt = raw[P + q] - features[static_cast<std::size_t>(pt) * P + q];
    EXPECT_FLOAT_EQ(target[q], std::asinh(dn / 8.0f)) << q;
    EXPECT_FLOAT_EQ(target[P + q], std::asinh(dt / 8.0f)) << q;
  }
  // The inverse path: expand, then add λ_prev back — the data set's label again.
  Tensor back = target;
  expand_labels(back, def.scale);
  for (std::size_t q = 0; q < P; ++q) {
    EXPECT_NEAR(back[q] + features[static_cast<std::size_t>(pn) * P + q], raw[q], 1e-3 * (1 + std::abs(raw[q])));
    EXPECT_NEAR(back[P + q] + features[static_cast<std::size_t>(pt) * P + q], raw[P + q],
                1e-3 * (1 + std::abs(raw[P + q])));
  }
}

TEST(Labels, AbsoluteTargetIgnoresLambdaPrevAndScaleZeroIsTheIdentity) {
  const std::vector<FeatureChannel> ch = default_feature_channels();  // no lambda_prev channels
  const Tensor features = random_tensor(static_cast<int>(ch.size()), 4, 3, 3, 1.0);
  const Tensor raw = random_tensor(2, 4, 3, 4, 50.0);
  Tensor t = raw;
  training_labels(t, features, ch, LabelDef{});
  for (std::size_t i = 0; i < raw.size(); ++i) EXPECT_EQ(t[i], raw[i]);
  // A residual definition needs the lambda_prev channels; shapes must agree.
  EXPECT_THROW(training_labels(t, features, ch, LabelDef{LabelKind::Residual, 0.0, 0.0}), ConfigError);
  Tensor wrong(1, 2, 3, 3);
  EXPECT_THROW(training_labels(wrong, features, ch, LabelDef{}), InvalidArgument);
}

TEST(Labels, DeadzoneSoftThresholds) {
  std::vector<double> v{-3.0, -0.5, 0.0, 0.2, 0.5, 2.0};
  apply_deadzone(v, 0.5);
  EXPECT_EQ(v, (std::vector<double>{-2.5, 0.0, 0.0, 0.0, 0.0, 1.5}));
  std::vector<double> same{-1.0, 0.25};
  apply_deadzone(same, 0.0);  // off
  EXPECT_EQ(same, (std::vector<double>{-1.0, 0.25}));
}

}  // namespace
}  // namespace dc
