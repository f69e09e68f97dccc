#pragma once
// Layer: the interface every CNN building block implements.
//
// Activations are owned by the caller (the Network graph), not by the layers: forward
// writes y from x, and backward receives the same x and y again. That way skip
// connections and backward passes never copy activations, and a layer can be
// gradient-checked in isolation. Layers keep only what they cannot recompute (dropout
// masks) plus reusable per-thread scratch buffers.
//
// Batch semantics: x is [N, C, H, W]; everything is per sample except that parameter
// gradients are summed over the batch (the loss is responsible for any 1/N).
#include <cstddef>
#include <string>
#include <vector>

#include "dc/learning/tensor.hpp"

namespace dc {

class Initializer;
class Rng;

/// A trainable parameter and its gradient, as handed to the optimiser.
struct ParamRef {
  std::string name;     ///< "<layer name>/weight", "<layer name>/bias"
  Tensor* value = nullptr;
  Tensor* grad = nullptr;
  bool decay = true;    ///< subject to L2 weight decay (weights yes, biases no)
};

class Layer {
 public:
  virtual ~Layer() = default;
  Layer() = default;
  Layer(const Layer&) = delete;
  Layer& operator=(const Layer&) = delete;

  /// Short type tag used in the arch format ("conv", "relu", "dropout", "dense", "upsample").
  [[nodiscard]] virtual std::string type() const = 0;
  /// One-line human-readable configuration, e.g. "conv 16->32 k3 s2 relu".
  [[nodiscard]] virtual std::string describe() const = 0;
  /// Output shape for an input of shape `in`; throws InvalidArgument when incompatible.
  [[nodiscard]] virtual Shape output_shape(const Shape& in) const = 0;

  /// y ← f(x). `y` is resized as needed (its buffer is reused across calls).
  /// `training` switches dropout on; all other layers ignore it.
  virtual void forward(const Tensor& x, Tensor& y, bool training) = 0;
  /// Given x, y = f(x) from the last forward and dL/dy, overwrite the parameter gradients
  /// with dL/dθ (summed over the batch) and, if dx is non-null, write dL/dx into it.
  virtual void backward(const Tensor& x, const Tensor& y, const Tensor& dy, Tensor* dx) = 0;

  /// Parameters and gradients (empty for parameter-free layers). Pointers stay valid for
  /// the layer's lifetime.
  virtual std::vector<ParamRef> parameters() { return {}; }
  /// Draw initial weights (biases are zeroed).
  virtual void initialize(const Initializer& /*init*/, Rng& /*rng*/) {}
  /// Number of scalar parameters.
  [[nodiscard]] std::size_t parameter_count();
};

}  // namespace dc
