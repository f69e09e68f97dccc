// The label definition of a model, both directions (labels.hpp).
#include "dc/learning/labels.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "dc/core/error.hpp"
#include "det_sinh.hpp"

namespace dc {

const char* to_string(LabelKind kind) {
  switch (kind) {
    case LabelKind::Absolute: return "absolute";
    case LabelKind::Residual: return "residual";
    case LabelKind::Gain: return "gain";
  }
  return "?";
}

LabelKind parse_label_kind(std::string_view text) {
  for (const LabelKind k : {LabelKind::Absolute, LabelKind::Residual, LabelKind::Gain})
    if (text == to_string(k)) return k;
  throw ConfigError("label kind '" + std::string(text) + "': expected absolute, residual or gain");
}

void LabelDef::validate() const {
  if (!(scale >= 0) || !std::isfinite(scale)) throw ConfigError("label_scale must be a finite number >= 0");
  if (!(deadzone >= 0) || !std::isfinite(deadzone))
    throw ConfigError("correction_deadzone must be a finite number >= 0");
}

void compress_labels(Tensor& labels, double scale) {
  if (scale <= 0) return;
  const float inv = static_cast<float>(1.0 / scale);
  for (float& v : labels.flat()) v = std::asinh(v * inv);
}

void expand_label_values(std::span<float> values, double scale) {
  if (scale <= 0) return;
  const float s = static_cast<float>(scale);
  float* v = values.data();
  const std::size_t n = values.size();
  for (std::size_t i = 0; i < n; ++i) v[i] = s * detail::det_sinhf(v[i]);
}

void expand_labels(Tensor& labels, double scale) { expand_label_values(std::span<float>(labels.data(), labels.size()), scale); }

std::pair<int, int> lambda_prev_channels(std::span<const FeatureChannel> channels, std::string_view what) {
  const auto index = [&](FeatureChannel c) {
    const auto it = std::find(channels.begin(), channels.end(), c);
    if (it == channels.end())
      throw ConfigError(std::string(what) + ": a residual model needs the feature channel " + to_string(c));
    return static_cast<int>(it - channels.begin());
  };
  return {index(FeatureChannel::LambdaPrevN), index(FeatureChannel::LambdaPrevT)};
}

void training_labels(Tensor& labels, const Tensor& features, std::span<const FeatureChannel> channels,
                     const LabelDef& def) {
  require_shape(labels.shape(), Shape{1, kLabelChannelCount, features.h(), features.w()},
                "training_labels: labels");
  require_shape(features.shape(), Shape{1, static_cast<int>(channels.size()), labels.h(), labels.w()},
                "training_labels: features");
  if (def.kind == LabelKind::Gain)
    throw ConfigError("training labels: a gain model has no label grid (train it through PGS: --loss pgs-* --gain)");
  if (def.kind == LabelKind::Residual) {
    const auto [prev_n, prev_t] = lambda_prev_channels(channels, "training labels");
    const std::size_t P = features.shape().plane();
    for (int c = 0; c < 2; ++c) {
      const float* prev = features.data() + static_cast<std::size_t>(c == 0 ? prev_n : prev_t) * P;
      float* lab = labels.data() + static_cast<std::size_t>(c) * P;
      for (std::size_t q = 0; q < P; ++q) lab[q] -= prev[q];
    }
  }
  compress_labels(labels, def.scale);
}

void apply_deadzone(std::span<double> values, double tau) {
  if (!(tau > 0)) return;
  for (double& d : values) d = d > tau ? d - tau : (d < -tau ? d + tau : 0.0);
}

}  // namespace dc
