#include "dc/learning/model.hpp"

#include <algorithm>
#include <cmath>

#include "dc/engine/error.hpp"

namespace dc {

namespace {
void fill_names(std::vector<std::string>& names, int count, const char* prefix, const char* what) {
  if (names.empty())
    for (int i = 0; i < count; ++i) names.push_back(prefix + std::to_string(i));
  if (static_cast<int>(names.size()) != count)
    throw InvalidArgument(std::string("Model: ") + what + " lists " + std::to_string(names.size()) +
                          " channel names but the network has " + std::to_string(count) + " channels");
}
}  // namespace

void validate_label_kind(const std::string& kind) {
  if (kind != "absolute" && kind != "residual")
    throw ConfigError("label kind '" + kind + "': expected 'absolute' or 'residual'");
}

Model::Model(ArchSpec arch, ModelGrid grid, int in_channels)
    : grid_(std::move(grid)), net_(std::move(arch), Shape{1, in_channels, grid_.ny, grid_.nx}) {
  validate_label_kind(grid_.label_kind);
  if (!(grid_.label_scale >= 0) || !std::isfinite(grid_.label_scale))
    throw ConfigError("Model: label_scale must be a finite number >= 0");
  if (!(grid_.correction_deadzone >= 0) || !std::isfinite(grid_.correction_deadzone))
    throw ConfigError("Model: correction_deadzone must be a finite number >= 0");
  fill_names(grid_.feature_channels, in_channels, "f", "feature_channels");
  fill_names(grid_.label_channels, net_.output_shape().c, "l", "label_channels");
  input_stats = ChannelStats::identity(in_channels);
  output_stats = ChannelStats::identity(net_.output_shape().c);
  if (grid_.label_kind == "residual") {
    const auto& f = grid_.feature_channels;
    for (const char* need : {"lambda_prev_n", "lambda_prev_t"})
      if (std::find(f.begin(), f.end(), need) == f.end())
        throw ConfigError(std::string("Model: a residual model needs the feature channel ") + need);
  }
}

Tensor Model::predict(const Tensor& features) {
  scratch_ = features;
  input_stats.apply(scratch_);
  Tensor out = net_.forward(scratch_, false);
  output_stats.invert(out);
  expand_labels(out, grid_.label_scale);
  return out;
}

void compress_labels(Tensor& labels, double scale) {
  if (scale <= 0) return;
  const float inv = static_cast<float>(1.0 / scale);
  for (float& v : labels.flat()) v = std::asinh(v * inv);
}

void expand_labels(Tensor& labels, double scale) {
  if (scale <= 0) return;
  const float s = static_cast<float>(scale);
  for (float& v : labels.flat()) v = s * std::sinh(v);
}

}  // namespace dc
