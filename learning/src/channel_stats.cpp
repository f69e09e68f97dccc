#include "dc/learning/channel_stats.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "dc/core/error.hpp"

namespace dc {

ChannelStats ChannelStats::identity(int channels) {
  return {std::vector<float>(static_cast<std::size_t>(channels), 0.0f),
          std::vector<float>(static_cast<std::size_t>(channels), 1.0f)};
}

ChannelStats ChannelStats::compute(std::span<const Tensor* const> tensors) {
  if (tensors.empty()) throw InvalidArgument("ChannelStats::compute: no tensors");
  ChannelStatsAccumulator acc;
  for (const Tensor* t : tensors) acc.add(*t);
  return acc.finish();
}

void ChannelStatsAccumulator::add(const Tensor& t) {
  if (channels_ < 0) {
    channels_ = t.c();
    sum_.assign(static_cast<std::size_t>(channels_), 0.0);
    sq_.assign(static_cast<std::size_t>(channels_), 0.0);
  }
  const int C = channels_;
  if (t.c() != C) throw InvalidArgument("ChannelStats::compute: channel count " + std::to_string(t.c()) +
                                        " != " + std::to_string(C));
  const std::size_t plane = t.shape().plane();
  for (int n = 0; n < t.n(); ++n)
    for (int c = 0; c < C; ++c) {
      const float* p = t.sample(n) + static_cast<std::size_t>(c) * plane;
      for (std::size_t i = 0; i < plane; ++i) {
        sum_[static_cast<std::size_t>(c)] += p[i];
        sq_[static_cast<std::size_t>(c)] += double(p[i]) * p[i];
      }
    }
  count_ += double(t.n()) * plane;
}

ChannelStats ChannelStatsAccumulator::finish() const {
  if (channels_ < 0) throw InvalidArgument("ChannelStats::compute: no tensors");
  if (count_ == 0.0) throw InvalidArgument("ChannelStats::compute: no pixels");
  ChannelStats s;
  for (int c = 0; c < channels_; ++c) {
    const double m = sum_[static_cast<std::size_t>(c)] / count_;
    const double var = std::max(sq_[static_cast<std::size_t>(c)] / count_ - m * m, 0.0);
    const double sd = std::sqrt(var);
    s.mean.push_back(static_cast<float>(m));
    // A (nearly) constant channel carries no information; std 1 avoids blowing up noise.
    s.std.push_back(sd > 1e-8 * std::max(1.0, std::abs(m)) ? static_cast<float>(sd) : 1.0f);
  }
  return s;
}

void ChannelStats::apply(Tensor& t) const {
  if (t.c() != channels() || std.size() != mean.size())
    throw InvalidArgument("ChannelStats::apply: tensor has " + std::to_string(t.c()) + " channels, stats have " +
                          std::to_string(channels()));
  const std::size_t plane = t.shape().plane();
  for (int n = 0; n < t.n(); ++n)
    for (int c = 0; c < t.c(); ++c) {
      float* p = t.sample(n) + static_cast<std::size_t>(c) * plane;
      const float m = mean[static_cast<std::size_t>(c)], inv = 1.0f / std[static_cast<std::size_t>(c)];
      for (std::size_t i = 0; i < plane; ++i) p[i] = (p[i] - m) * inv;
    }
}

void ChannelStats::invert(Tensor& t) const {
  if (t.c() != channels() || std.size() != mean.size())
    throw InvalidArgument("ChannelStats::invert: tensor has " + std::to_string(t.c()) + " channels, stats have " +
                          std::to_string(channels()));
  const std::size_t plane = t.shape().plane();
  for (int n = 0; n < t.n(); ++n)
    for (int c = 0; c < t.c(); ++c) {
      float* p = t.sample(n) + static_cast<std::size_t>(c) * plane;
      const float m = mean[static_cast<std::size_t>(c)], s = std[static_cast<std::size_t>(c)];
      for (std::size_t i = 0; i < plane; ++i) p[i] = p[i] * s + m;
    }
}

}  // namespace dc
