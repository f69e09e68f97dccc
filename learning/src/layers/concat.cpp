#include "dc/learning/layers/concat.hpp"

#include <cstring>

#include "dc/core/error.hpp"

namespace dc {

Shape concat_shape(std::span<const Shape> inputs) {
  if (inputs.empty()) throw InvalidArgument("concat: no inputs");
  Shape out = inputs[0];
  for (std::size_t i = 1; i < inputs.size(); ++i) {
    const Shape& s = inputs[i];
    if (s.n != out.n || s.h != out.h || s.w != out.w)
      throw InvalidArgument("concat: input " + std::to_string(i) + " shape " + s.str() +
                            " does not match " + inputs[0].str() + " in N, H, W");
    out.c += s.c;
  }
  return out;
}

void concat_channels(std::span<const Tensor* const> inputs, Tensor& y) {
  std::vector<Shape> shapes;
  for (const Tensor* t : inputs) shapes.push_back(t->shape());
  const Shape out = concat_shape(shapes);
  y.resize(out);
  // Per sample the channels of each input are one contiguous block of C_i·H·W floats.
  for (int n = 0; n < out.n; ++n) {
    float* dst = y.sample(n);
    for (const Tensor* t : inputs) {
      const std::size_t len = t->shape().sample_count();
      std::memcpy(dst, t->sample(n), sizeof(float) * len);
      dst += len;
    }
  }
}

void split_channels(const Tensor& dy, std::span<Tensor* const> grads, std::span<const bool> accumulate) {
  if (grads.size() != accumulate.size()) throw InvalidArgument("split_channels: grads/accumulate size mismatch");
  int channels = 0;
  for (Tensor* g : grads) {
    if (g == nullptr) throw InvalidArgument("split_channels: null gradient tensor");
    if (g->n() != dy.n() || g->h() != dy.h() || g->w() != dy.w())
      throw InvalidArgument("split_channels: gradient " + g->shape().str() + " does not match " + dy.shape().str());
    channels += g->c();
  }
  if (channels != dy.c()) throw InvalidArgument("split_channels: channel sum mismatch for " + dy.shape().str());
  for (int n = 0; n < dy.n(); ++n) {
    const float* src = dy.sample(n);
    for (std::size_t i = 0; i < grads.size(); ++i) {
      const std::size_t len = grads[i]->shape().sample_count();
      float* dst = grads[i]->sample(n);
      if (accumulate[i]) {
        for (std::size_t j = 0; j < len; ++j) dst[j] += src[j];
      } else {
        std::memcpy(dst, src, sizeof(float) * len);
      }
      src += len;
    }
  }
}

}  // namespace dc
