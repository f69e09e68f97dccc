#include "dc/learning/layers/relu.hpp"

namespace dc {

void ReLU::forward(const Tensor& x, Tensor& y, bool /*training*/) {
  y.resize(x.shape());
  y.flat() = x.flat().cwiseMax(0.0f);
}

void ReLU::backward(const Tensor& /*x*/, const Tensor& y, const Tensor& dy, Tensor* dx) {
  require_shape(dy.shape(), y.shape(), "ReLU::backward dy");
  if (dx == nullptr) return;
  dx->resize(y.shape());
  dx->flat() = (y.flat().array() > 0.0f).select(dy.flat(), 0.0f);
}

}  // namespace dc
