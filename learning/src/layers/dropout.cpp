#include "dc/learning/layers/dropout.hpp"

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"

namespace dc {

Dropout::Dropout(double rate, Rng* rng) : p_(rate), rng_(rng) {
  if (!(rate >= 0.0 && rate < 1.0)) throw InvalidArgument("Dropout: rate must be in [0, 1), got " + std::to_string(rate));
}

std::string Dropout::describe() const { return "dropout p=" + std::to_string(p_); }

void Dropout::forward(const Tensor& x, Tensor& y, bool training) {
  y.resize(x.shape());
  identity_ = !training || p_ == 0.0;
  if (identity_) {
    y.flat() = x.flat();
    return;
  }
  if (rng_ == nullptr) throw InvalidArgument("Dropout: training forward needs a dc::Rng (set_rng)");
  mask_.resize(x.shape());
  const float keep_scale = static_cast<float>(1.0 / (1.0 - p_));
  const std::size_t per = x.n() > 0 ? mask_.size() / static_cast<std::size_t>(x.n()) : 0;
  const int total = window_total_ > 0 ? window_total_ : x.n(), offset = window_total_ > 0 ? window_offset_ : 0;
  if (offset < 0 || offset + x.n() > total)
    throw InvalidArgument("Dropout: batch window [" + std::to_string(offset) + ", " + std::to_string(offset + x.n()) +
                          ") outside a batch of " + std::to_string(total));
  for (std::size_t i = 0; i < static_cast<std::size_t>(offset) * per; ++i) (void)rng_->uniform();
  for (std::size_t i = 0; i < mask_.size(); ++i) mask_[i] = rng_->uniform() >= p_ ? keep_scale : 0.0f;
  for (std::size_t i = 0; i < static_cast<std::size_t>(total - offset - x.n()) * per; ++i) (void)rng_->uniform();
  y.flat() = x.flat().cwiseProduct(mask_.flat());
}

void Dropout::backward(const Tensor& x, const Tensor& /*y*/, const Tensor& dy, Tensor* dx) {
  require_shape(dy.shape(), x.shape(), "Dropout::backward dy");
  if (dx == nullptr) return;
  dx->resize(x.shape());
  if (identity_) {
    dx->flat() = dy.flat();
  } else {
    require_shape(mask_.shape(), dy.shape(), "Dropout::backward mask");
    dx->flat() = dy.flat().cwiseProduct(mask_.flat());
  }
}

}  // namespace dc
