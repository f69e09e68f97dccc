#pragma once
// Mean squared error with optional per-element weights (e.g. heavier near contacts, or a
// 0/1 mask):
//   L = Σ_i w_i (p_i − t_i)² / Σ_i w_i,     ∂L/∂p_i = 2 w_i (p_i − t_i) / Σ_i w_i.
// Without weights w_i = 1 and L is the plain mean over all N·C·H·W elements. Weights have
// the prediction's shape, or C = 1 to share one weight map across channels. Sums run in
// double. If Σ w = 0 the loss and gradient are 0.
#include "dc/learning/tensor.hpp"

namespace dc {

class MseLoss {
 public:
  /// Returns L; if grad is non-null it receives ∂L/∂pred (resized). Throws
  /// InvalidArgument on shape mismatch or negative weights.
  double operator()(const Tensor& pred, const Tensor& target, const Tensor* weight = nullptr,
                    Tensor* grad = nullptr) const;
};

}  // namespace dc
