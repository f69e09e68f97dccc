// InMemorySamples: the SampleSource over a vector of samples (sample_source.hpp).
#include "dc/learning/sample_source.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "dc/core/error.hpp"

namespace dc {

InMemorySamples::InMemorySamples(std::span<const TrainingSample> samples) : samples_(samples) {
  if (samples_.empty()) return;
  xs_ = samples_[0].features.shape();
  ys_ = samples_[0].labels.shape();
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    const TrainingSample& s = samples_[i];
    const std::string where = "InMemorySamples: sample " + std::to_string(i);
    require_shape(s.features.shape(), xs_, where + " features");
    require_shape(s.labels.shape(), ys_, where + " labels");
    if (s.weights.empty()) continue;
    const int c = s.weights.c();
    if (!(s.weights.shape() == ys_) && !(s.weights.shape() == Shape{1, 1, ys_.h, ys_.w}))
      throw InvalidArgument(where + " weights: shape " + s.weights.shape().str() + " fits neither labels nor C = 1");
    if (wc_ != 0 && c != wc_) throw InvalidArgument(where + " weights: channel count differs from earlier samples");
    wc_ = c;
  }
}

void InMemorySamples::read(std::span<const std::size_t> indices, Tensor& x, Tensor& y, Tensor& w) const {
  const int k = static_cast<int>(indices.size());
  x.resize(xs_.with_batch(k));
  y.resize(ys_.with_batch(k));
  const std::size_t wlen = static_cast<std::size_t>(wc_) * ys_.plane();
  if (wc_ > 0) w.resize({k, wc_, ys_.h, ys_.w});
  for (int j = 0; j < k; ++j) {
    const TrainingSample& s = samples_[indices[static_cast<std::size_t>(j)]];
    std::memcpy(x.sample(j), s.features.data(), sizeof(float) * xs_.sample_count());
    std::memcpy(y.sample(j), s.labels.data(), sizeof(float) * ys_.sample_count());
    if (wc_ == 0) continue;
    if (s.weights.empty()) std::fill(w.sample(j), w.sample(j) + wlen, 1.0f);
    else std::memcpy(w.sample(j), s.weights.data(), sizeof(float) * wlen);
  }
}

}  // namespace dc
