#include "dc/learning/model.hpp"

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

/// The grid checked before the network is sized by it.
ModelGrid validated(ModelGrid g) {
  try {
    g.image.validate();
    g.labels.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(std::string("Model: ") + e.what());
  }
  if (g.labels.kind == LabelKind::Residual) (void)lambda_prev_channels(g.image.channels, "Model");
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
  scratch_ = features;
  input_stats.apply(scratch_);
  Tensor out = net_.forward(scratch_, false);
  output_stats.invert(out);
  expand_labels(out, grid_.labels.scale);
  return out;
}

}  // namespace dc
