// labels.hpp: the one definition of a model's labels — the training target (train) and its
// inverse (Model::predict + the cnn starter's read-back) undo each other.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
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

namespace dc {
namespace {

/// Distance in units in the last place between two finite floats of the same sign.
long ulp_distance(float a, float b) {
  std::int32_t ia = 0, ib = 0;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  return std::labs(static_cast<long>(ia) - static_cast<long>(ib));
}

// The label expansion's sinh (learning/src/det_sinh.hpp) is libm-free; it must still be sinh:
// within one ulp of long double sinhl rounded to float everywhere, and that correctly rounded
// value nearly always (it errs only where sinh z lies within ~3e-16 of a rounding midpoint);
// odd bit for bit, ±inf beyond FLT_MAX (z ≥ 89.42), NaN for NaN, ±0 for ±0.
TEST(Labels, ExpansionSinhIsWithinOneUlpOfLongDoubleSinh) {
  std::vector<float> z;
  for (double m = 1e-30; m < 89.0; m *= 1.0007) z.push_back(static_cast<float>(m));  // ~1.3e5 magnitudes
  Rng rng(11);
  for (int k = 0; k < 100000; ++k) z.push_back(static_cast<float>(rng.uniform(0.0, 12.0)));
  const std::size_t n = z.size();
  for (std::size_t k = 0; k < n; ++k) z.push_back(-z[k]);
  std::vector<float> got = z;
  expand_label_values(got, 1.0);  // 1.0f · sinh z: exactly sinh z
  long worst = 0;
  std::size_t off = 0;
  for (std::size_t k = 0; k < z.size(); ++k) {
    const float want = static_cast<float>(std::sinh(static_cast<long double>(z[k])));
    const long d = ulp_distance(got[k], want);
    worst = std::max(worst, d);
    off += d != 0;
    if (k < n) ASSERT_EQ(ulp_distance(got[k + n], -got[k]), 0) << "sinh(-z) = -sinh(z) at z = " << z[k];
  }
  EXPECT_LE(worst, 1);
  RecordProperty("not_correctly_rounded", static_cast<int>(off));
  EXPECT_LT(off, z.size() / 1000) << off << " of " << z.size() << " not the correctly rounded float";
  std::vector<float> edge = {89.5f, -89.5f, 1e30f, std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                             0.0f, -0.0f, 89.4f};
  expand_label_values(edge, 1.0);
  EXPECT_EQ(edge[0], std::numeric_limits<float>::infinity());
  EXPECT_EQ(edge[1], -std::numeric_limits<float>::infinity());
  EXPECT_EQ(edge[2], std::numeric_limits<float>::infinity());
  EXPECT_EQ(edge[3], std::numeric_limits<float>::infinity());
  EXPECT_EQ(edge[4], -std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(edge[5]));
  EXPECT_TRUE(edge[6] == 0.0f && !std::signbit(edge[6]));
  EXPECT_TRUE(edge[7] == 0.0f && std::signbit(edge[7]));
  EXPECT_TRUE(std::isfinite(edge[8]));
  EXPECT_EQ(ulp_distance(edge[8], static_cast<float>(std::sinh(static_cast<long double>(89.4f)))), 0);
}

}  // namespace
}  // namespace dc
