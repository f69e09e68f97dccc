#pragma once
// ReLU: y = max(x, 0), dx = dy · [y > 0] (the subgradient at 0 is taken as 0).
// Conv2d and Dense can fuse the same operation (relu = true) to save a memory pass;
// this stand-alone layer exists for arch files that want it explicitly.
#include "dc/learning/layers/layer.hpp"

namespace dc {

class ReLU final : public Layer {
 public:
  [[nodiscard]] std::string type() const override { return "relu"; }
  [[nodiscard]] std::string describe() const override { return "relu"; }
  [[nodiscard]] Shape output_shape(const Shape& in) const override { return in; }
  void forward(const Tensor& x, Tensor& y, bool training) override;
  void backward(const Tensor& x, const Tensor& y, const Tensor& dy, Tensor* dx) override;
};

}  // namespace dc
