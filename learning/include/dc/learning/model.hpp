#pragma once
// Model: everything needed to turn a raw feature grid into a raw label grid — the network,
// the per-channel standardisation of inputs and outputs, and the grid it was trained for.
// Persisted by save_model / load_model (model_file.hpp).
#include <span>
#include <string>
#include <vector>

#include "dc/learning/channel_stats.hpp"
#include "dc/learning/feature_channels.hpp"
#include "dc/learning/labels.hpp"
#include "dc/learning/network.hpp"

namespace dc {

/// The grid a model was trained on (docs/design.md §4) and what its input and output mean:
/// the feature image it reads (kernel, node spacing, support, channels), its output channel
/// names and the label definition. The default is a valid model grid: the data set's
/// default feature image on a 30 × 30 box (61 × 61 nodes), absolute labels.
struct ModelGrid {
  /// The feature image of the training data: image.sph.kernel, image.sph.grid.spacing (d),
  /// image.sph.support (h), image.channels, on the training box image.sph.grid.width/height.
  /// A user rebuilds it on its own box and requires the same node counts.
  /// A loaded model's box is (nx − 1)·d × (ny − 1)·d: the file stores node counts only.
  FeatureImageDef image = FeatureImageDef::for_box(30.0, 30.0);
  /// Output channel names, in order ("lambda_n", "lambda_t" for a warm-start model; an empty
  /// list is filled with "l0", "l1", …).
  std::vector<std::string> label_channels = label_channel_names();
  /// What the label grid means (absolute or residual, asinh scale, dead zone).
  LabelDef labels;
  [[nodiscard]] int nx() const;  ///< nodes along x of image (columns)
  [[nodiscard]] int ny() const;  ///< nodes along y (rows)
};

class Model {
 public:
  /// Network for inputs [in_channels, grid.ny(), grid.nx()]; stats start as the identity.
  /// Throws ConfigError when the arch does not fit or the grid is invalid (image, labels,
  /// a residual model without the lambda_prev channels), InvalidArgument when the number
  /// of feature channels is not in_channels or the label names do not match the network's
  /// output channels.
  Model(ArchSpec arch, ModelGrid grid, int in_channels);

  /// Raw features [N, C_in, ny, nx] → raw labels [N, C_out, ny, nx] (inference mode).
  /// Equals label_value() of network_output() at every node.
  Tensor predict(const Tensor& features);
  /// The network's output for raw features, in standardised (and compressed) label units:
  /// features standardised, then the network in inference mode. The reference stays valid
  /// until the next call. The cnn starter de-standardises only the nodes it reads back.
  const Tensor& network_output(const Tensor& features);
  /// The same at selected output pixels only (Network::forward_at: the other pixels are
  /// unspecified).
  const Tensor& network_output_at(const Tensor& features, std::span<const int> pixels);
  /// The raw label of output channel c from the network's output value y at one node:
  /// expand(y·std_c + mean_c) — exactly what predict() computes there (float arithmetic).
  [[nodiscard]] float label_value(int c, float y) const;
  /// label_value(c, y) for every y of `ys` in place, bit for bit (the expansion vectorised).
  void label_values(int c, std::span<float> ys) const;

  [[nodiscard]] const ModelGrid& grid() const { return grid_; }
  Network& network() { return net_; }
  ChannelStats input_stats;   ///< standardisation of features (C_in entries)
  ChannelStats output_stats;  ///< standardisation of labels (C_out entries)

 private:
  ModelGrid grid_;
  Network net_;
  Tensor scratch_, out_;
};

}  // namespace dc
