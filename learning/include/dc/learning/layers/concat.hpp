#pragma once
// Channel concatenation, the join of a skip connection: inputs [N, C_i, H, W] (same N, H,
// W) → y [N, Σ C_i, H, W], input i occupying channels [Σ_{j<i} C_j, Σ_{j≤i} C_j).
// Its adjoint splits dy back into per-input channel slices. The Network applies it to a
// node with several inputs before the node's layer runs.
#include <span>

#include "dc/learning/tensor.hpp"

namespace dc {

/// Shape of the concatenation; throws InvalidArgument on empty input or N/H/W mismatch.
Shape concat_shape(std::span<const Shape> inputs);
/// y ← concat(inputs) along channels (y is resized).
void concat_channels(std::span<const Tensor* const> inputs, Tensor& y);
/// Adjoint: for each i, grads[i] (shape of input i) gets its channel slice of dy —
/// assigned when accumulate[i] is false, added otherwise. A null grads[i] is skipped.
void split_channels(const Tensor& dy, std::span<Tensor* const> grads, std::span<const bool> accumulate);

}  // namespace dc
