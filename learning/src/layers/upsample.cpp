#include "dc/learning/layers/upsample.hpp"

#include <cstring>

#include "dc/core/error.hpp"

namespace dc {

Upsample2x::Upsample2x(int out_h, int out_w) : out_h_(out_h), out_w_(out_w) {
  if (out_h < 0 || out_w < 0) throw InvalidArgument("Upsample2x: negative output size");
}

std::string Upsample2x::describe() const {
  if (out_h_ == 0 && out_w_ == 0) return "upsample x2";
  return "upsample x2 -> " + std::to_string(out_h_) + "x" + std::to_string(out_w_);
}

Shape Upsample2x::output_shape(const Shape& in) const {
  const int ho = out_h_ > 0 ? out_h_ : 2 * in.h;
  const int wo = out_w_ > 0 ? out_w_ : 2 * in.w;
  if (in.h <= 0 || in.w <= 0 || (ho != 2 * in.h && ho != 2 * in.h - 1) || (wo != 2 * in.w && wo != 2 * in.w - 1))
    throw InvalidArgument("Upsample2x: output " + std::to_string(ho) + "x" + std::to_string(wo) +
                          " is not 2x (or 2x-1) of input " + in.str());
  return {in.n, in.c, ho, wo};
}

void Upsample2x::forward(const Tensor& x, Tensor& y, bool /*training*/) {
  const Shape out = output_shape(x.shape());
  y.resize(out);
  const int planes = x.n() * x.c();
  const int H = x.h(), W = x.w(), Ho = out.h, Wo = out.w;
#pragma omp parallel for schedule(static) if (static_cast<long>(planes) * Ho * Wo >= (1L << 17))
  for (int p = 0; p < planes; ++p) {
    const float* src = x.data() + static_cast<std::size_t>(p) * H * W;
    float* dst = y.data() + static_cast<std::size_t>(p) * Ho * Wo;
    for (int Y = 0; Y < Ho; ++Y) {
      const float* s = src + static_cast<std::size_t>(Y / 2) * W;
      float* d = dst + static_cast<std::size_t>(Y) * Wo;
      if (Y % 2 == 1) {  // odd output rows repeat the row above
        std::memcpy(d, d - Wo, sizeof(float) * Wo);
        continue;
      }
      for (int X = 0; X < Wo; ++X) d[X] = s[X / 2];
    }
  }
}

void Upsample2x::backward(const Tensor& x, const Tensor& /*y*/, const Tensor& dy, Tensor* dx) {
  const Shape out = output_shape(x.shape());
  require_shape(dy.shape(), out, "Upsample2x::backward dy");
  if (dx == nullptr) return;
  dx->resize(x.shape());
  const int planes = x.n() * x.c();
  const int H = x.h(), W = x.w(), Ho = out.h, Wo = out.w;
#pragma omp parallel for schedule(static) if (static_cast<long>(planes) * Ho * Wo >= (1L << 17))
  for (int p = 0; p < planes; ++p) {
    const float* g = dy.data() + static_cast<std::size_t>(p) * Ho * Wo;
    float* d = dx->data() + static_cast<std::size_t>(p) * H * W;
    std::memset(d, 0, sizeof(float) * H * W);
    for (int Y = 0; Y < Ho; ++Y) {
      float* row = d + static_cast<std::size_t>(Y / 2) * W;
      const float* gr = g + static_cast<std::size_t>(Y) * Wo;
      for (int X = 0; X < Wo; ++X) row[X / 2] += gr[X];
    }
  }
}

}  // namespace dc
