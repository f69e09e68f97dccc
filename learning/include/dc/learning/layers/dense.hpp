#pragma once
// Dense (fully connected) layer on the flattened sample: x [N, C, H, W] is read as N
// vectors of D = C·H·W, y [N, Co, Ho, Wo] as N vectors of O = Co·Ho·Wo (so a dense head can
// emit a whole label image, as seed_dense_arch does).
//
//   y = W x + b,  W [O, D] stored row-major = column-major D × O matrix Wᵀ.
//   Forward  Y (O × N) = Wᵀᵀ · X (D × N);   backward  dWᵀ = X · dYᵀ,  db = Σ_n dY,  dX = Wᵀ · dY.
// One GEMM for the whole batch; Eigen parallelises it over the OpenMP threads.
#include "dc/learning/layers/layer.hpp"

namespace dc {

class Dense final : public Layer {
 public:
  /// in_features = D; out = output sample shape (n ignored). Throws InvalidArgument if empty.
  Dense(int in_features, Shape out, bool relu = false);

  [[nodiscard]] std::string type() const override { return "dense"; }
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] Shape output_shape(const Shape& in) const override;
  void forward(const Tensor& x, Tensor& y, bool training) override;
  void backward(const Tensor& x, const Tensor& y, const Tensor& dy, Tensor* dx) override;
  std::vector<ParamRef> parameters() override;
  void initialize(const Initializer& init, Rng& rng) override;

  Tensor& weight() { return weight_; }  ///< [O, D, 1, 1]
  Tensor& bias() { return bias_; }      ///< [1, O, 1, 1]

 private:
  int in_;
  Shape out_;
  int out_features_;
  bool relu_;
  Tensor weight_, bias_, dweight_, dbias_;
  Tensor masked_;  ///< dY ⊙ [y > 0] when relu_
};

}  // namespace dc
