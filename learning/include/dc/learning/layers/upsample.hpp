#pragma once
// Upsample2x: nearest-neighbour ×2 up-sampling to an explicit output size, so that an
// encoder with odd sizes (61 → 31 → 16) can be mirrored exactly (16 → 31 → 61):
//   y[n, c, Y, X] = x[n, c, ⌊Y/2⌋, ⌊X/2⌋],  Ho ∈ {2H − 1, 2H}, Wo ∈ {2W − 1, 2W}.
// Backward is the exact adjoint: dx[n, c, i, j] = Σ_{⌊Y/2⌋ = i, ⌊X/2⌋ = j} dy[n, c, Y, X]
// (2 × 2 blocks, truncated at an odd border).
#include "dc/learning/layers/layer.hpp"

namespace dc {

class Upsample2x final : public Layer {
 public:
  /// out_h/out_w = 0 means 2·H / 2·W. The size is checked against the input in output_shape.
  explicit Upsample2x(int out_h = 0, int out_w = 0);

  [[nodiscard]] std::string type() const override { return "upsample"; }
  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] Shape output_shape(const Shape& in) const override;
  void forward(const Tensor& x, Tensor& y, bool training) override;
  void backward(const Tensor& x, const Tensor& y, const Tensor& dy, Tensor* dx) override;

 private:
  int out_h_, out_w_;
};

}  // namespace dc
