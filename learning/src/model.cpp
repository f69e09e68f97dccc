#include "dc/learning/model.hpp"

#include <cmath>

#include "dc/core/error.hpp"
#include "det_sinh.hpp"

namespace dc {

namespace {
void fill_names(std::vector<std::string>& names, int count, const char* prefix, const char* what) {
  if (names.empty())
    for (int i = 0; i < count; ++i) names.push_back(prefix + std::to_string(i));
  if (static_cast<int>(names.size()) != count)
    throw InvalidArgument(std::string("Model: ") + what + " lists " + std::to_string(names.size()) +
                          " channel names but the network has " + std::to_string(count) + " channels");
}

/// The grid checked before the network is sized by it.
ModelGrid validated(ModelGrid g) {
  try {
    g.image.validate();
    g.labels.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(std::string("Model: ") + e.what());
  }
  if (is_corrective(g.labels.kind)) (void)lambda_prev_channels(g.image.channels, "Model");
  return g;
}
}  // namespace

int ModelGrid::nx() const { return sph_node_count(image.sph.grid.width, image.sph.grid.spacing); }
int ModelGrid::ny() const { return sph_node_count(image.sph.grid.height, image.sph.grid.spacing); }

Model::Model(ArchSpec arch, ModelGrid grid, int in_channels)
    : grid_(validated(std::move(grid))), net_(std::move(arch), Shape{1, in_channels, grid_.ny(), grid_.nx()}) {
  if (static_cast<int>(grid_.image.channels.size()) != in_channels)
    throw InvalidArgument("Model: the feature image has " + std::to_string(grid_.image.channels.size()) +
                          " channels but the network reads " + std::to_string(in_channels));
  fill_names(grid_.label_channels, net_.output_shape().c, "l", "label_channels");
  input_stats = ChannelStats::identity(in_channels);
  output_stats = ChannelStats::identity(net_.output_shape().c);
}

Tensor Model::predict(const Tensor& features) {
  Tensor out = network_output(features);
  output_stats.invert(out);
  expand_labels(out, grid_.labels.scale);
  return out;
}

const Tensor& Model::network_output(const Tensor& features) {
  scratch_ = features;
  input_stats.apply(scratch_);
  return net_.forward(scratch_, false);
}

const Tensor& Model::network_output_at(const Tensor& features, std::span<const int> pixels) {
  scratch_ = features;
  input_stats.apply(scratch_);
  net_.forward_at(scratch_, pixels, out_);
  return out_;
}

float Model::label_value(int c, float y) const {
  const auto i = static_cast<std::size_t>(c);
  // The operations of ChannelStats::invert and expand_labels, in the same float order.
  const float v = y * output_stats.std[i] + output_stats.mean[i];
  const double scale = grid_.labels.scale;
  return scale > 0 ? static_cast<float>(scale) * detail::det_sinhf(v) : v;
}

void Model::label_values(int c, std::span<float> ys) const {
  const auto i = static_cast<std::size_t>(c);
  const float sd = output_stats.std[i], mean = output_stats.mean[i];
  for (float& y : ys) y = y * sd + mean;
  expand_label_values(ys, grid_.labels.scale);
}

}  // namespace dc
