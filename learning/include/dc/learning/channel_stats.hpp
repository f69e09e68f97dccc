#pragma once
// Per-channel standardisation z = (v − mean_c) / std_c of feature or label images. Computed
// from the training split only (so validation data never leaks into the model), stored in
// the model file, and inverted on the network's output at inference.
#include <span>
#include <vector>

#include "dc/learning/tensor.hpp"

namespace dc {

struct ChannelStats {
  std::vector<float> mean;  ///< per channel
  std::vector<float> std;   ///< per channel, > 0 (a constant channel gets std = 1)

  /// Identity statistics (mean 0, std 1) for C channels.
  static ChannelStats identity(int channels);
  /// Mean and population std over all samples and pixels of the listed tensors (all with
  /// the same C), accumulated in double in a fixed order. Throws InvalidArgument if empty.
  static ChannelStats compute(std::span<const Tensor* const> tensors);

  [[nodiscard]] int channels() const { return static_cast<int>(mean.size()); }
  /// In place: v ← (v − mean) / std. Throws InvalidArgument on a channel mismatch.
  void apply(Tensor& t) const;
  /// In place: v ← v · std + mean.
  void invert(Tensor& t) const;
};

/// ChannelStats::compute fed a tensor (of any batch size) at a time, for data that is never
/// all in memory: the same sums in the same order, so the same statistics bit for bit.
class ChannelStatsAccumulator {
 public:
  /// Adds every sample and pixel of t. InvalidArgument when t's channel count differs from
  /// the first tensor's.
  void add(const Tensor& t);
  /// The statistics of everything added; InvalidArgument when nothing (or no pixel) was.
  [[nodiscard]] ChannelStats finish() const;

 private:
  int channels_ = -1;
  std::vector<double> sum_, sq_;
  double count_ = 0.0;
};

}  // namespace dc
