#pragma once
// Model: everything needed to turn a raw feature grid into a raw label grid — the network,
// the per-channel standardisation of inputs and outputs, and the grid it was trained for.
// Persisted by save_model / load_model (model_file.hpp).
#include <string>
#include <vector>

#include "dc/learning/channel_stats.hpp"
#include "dc/learning/network.hpp"

namespace dc {

/// The grid a model was trained on (DESIGN §4): spacing d, kernel support h, kernel name,
/// node counts, and the channel names of features (input) and labels (output), in order.
struct ModelGrid {
  double d = 0.5;
  double h = 0.5;
  std::string kernel = "poly6";
  int nx = 61;
  int ny = 61;
  std::vector<std::string> feature_channels{"m", "v_x", "v_y", "omega"};
  std::vector<std::string> label_channels{"lambda_n", "lambda_t"};
  /// What the label grid means. "absolute": the Shepard numerators of λ* (the data set's
  /// labels). "residual": the numerators of λ* − λ_prev, i.e. the data set's labels minus the
  /// feature channels lambda_prev_n, lambda_prev_t (which the model must then have); the
  /// warm start is λ_prev (by key) plus the read-back of the predicted grid.
  std::string label_kind = "absolute";
  /// Output compression s ≥ 0 [label units]. s > 0: the network learns y = asinh(label / s)
  /// (standardised), so that small labels keep their precision next to heavy-tailed large
  /// ones (impacts carry 10³ N against a 50 N resting load); Model::predict returns
  /// s·sinh(y). 0 = labels as they are.
  double label_scale = 0.0;
  /// Residual models: soft threshold τ ≥ 0 [N] on the read-back correction of every row,
  /// δ ← sign(δ)·max(|δ| − τ, 0), before it is added to λ_prev. A correction within the
  /// network's noise level leaves builtin's value alone: on a settled pile builtin is exact
  /// and a 1–2 % correction noise would cost it ~50 sweeps (docs/learning.md). 0 = off.
  double correction_deadzone = 0.0;
};

/// The label compression of a model (ModelGrid::label_scale): asinh(v / s) and its inverse,
/// elementwise; the identity for s = 0.
void compress_labels(Tensor& labels, double scale);
void expand_labels(Tensor& labels, double scale);

/// "absolute" or "residual"; ConfigError otherwise.
void validate_label_kind(const std::string& kind);

class Model {
 public:
  /// Network for inputs [in_channels, grid.ny, grid.nx]; stats start as the identity.
  /// Throws ConfigError when the arch does not fit, InvalidArgument when the channel name
  /// lists do not match the network's input/output channels (empty lists are filled with
  /// "f0", "f1", … / "l0", …).
  Model(ArchSpec arch, ModelGrid grid, int in_channels);

  /// Raw features [N, C_in, ny, nx] → raw labels [N, C_out, ny, nx] (inference mode).
  Tensor predict(const Tensor& features);

  [[nodiscard]] const ModelGrid& grid() const { return grid_; }
  Network& network() { return net_; }
  ChannelStats input_stats;   ///< standardisation of features (C_in entries)
  ChannelStats output_stats;  ///< standardisation of labels (C_out entries)

 private:
  ModelGrid grid_;
  Network net_;
  Tensor scratch_;
};

}  // namespace dc
