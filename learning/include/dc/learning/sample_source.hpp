#pragma once
// Where the Trainer's samples come from: an indexable set of (features, labels, loss weights,
// simulation id) that is read a few samples at a time, so a data set larger than RAM can be
// trained on (docs/learning.md "Training", docs/robustness.md "Memory of train"). The Trainer
// holds at most its shuffle buffer and a few batches of samples (shuffle_stream.hpp); the
// source decides where the rest lives (InMemorySamples: a vector; the cnn library's
// DataSetSamples: an HDF5 data set read in runs of consecutive rows).
#include <cstddef>
#include <span>
#include <vector>

#include "dc/learning/tensor.hpp"

namespace dc {

/// One training example: [1, C_in, ny, nx] features, [1, C_out, ny, nx] labels, optional
/// loss weights [1, C_out or 1, ny, nx] (empty = all ones), and the simulation it came from.
struct TrainingSample {
  Tensor features;
  Tensor labels;
  Tensor weights;
  int simulation = 0;
};

/// N samples 0 … N − 1 of equal shapes, readable in any order and any number of times with
/// the same values (the Trainer reads the training split once for the standardisation and
/// again every epoch; the validation split every epoch).
class SampleSource {
 public:
  virtual ~SampleSource() = default;
  /// N.
  [[nodiscard]] virtual std::size_t size() const = 0;
  /// The simulation sample i came from (the train/validation split keeps simulations whole).
  [[nodiscard]] virtual int simulation(std::size_t i) const = 0;
  /// [1, C_in, ny, nx] and [1, C_out, ny, nx].
  [[nodiscard]] virtual Shape feature_shape() const = 0;
  [[nodiscard]] virtual Shape label_shape() const = 0;
  /// Channels of the loss weights: 0 (unweighted), 1 (shared by the label channels) or C_out.
  [[nodiscard]] virtual int weight_channels() const = 0;
  /// Samples `indices` (each < N; ascending indices let a file source read runs of rows):
  /// x ← [k, C_in, ny, nx], y ← [k, C_out, ny, nx] and, when weight_channels() > 0,
  /// w ← [k, weight channels, ny, nx] (unchanged otherwise). Raw values: the Trainer
  /// standardises them.
  virtual void read(std::span<const std::size_t> indices, Tensor& x, Tensor& y, Tensor& w) const = 0;
};

/// A SampleSource over samples already in memory (tests, Python, small runs). A sample
/// without weights has weight 1 everywhere when another sample has weights. The span must
/// outlive the source. InvalidArgument (naming the sample) when shapes differ between samples.
class InMemorySamples final : public SampleSource {
 public:
  explicit InMemorySamples(std::span<const TrainingSample> samples);
  [[nodiscard]] std::size_t size() const override { return samples_.size(); }
  [[nodiscard]] int simulation(std::size_t i) const override { return samples_[i].simulation; }
  [[nodiscard]] Shape feature_shape() const override { return xs_; }
  [[nodiscard]] Shape label_shape() const override { return ys_; }
  [[nodiscard]] int weight_channels() const override { return wc_; }
  void read(std::span<const std::size_t> indices, Tensor& x, Tensor& y, Tensor& w) const override;

 private:
  std::span<const TrainingSample> samples_;
  Shape xs_, ys_;
  int wc_ = 0;
};

}  // namespace dc
