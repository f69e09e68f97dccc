#include "dc/learning/contact_readback.hpp"

#include <string>

#include "dc/engine/error.hpp"

namespace dc {

ContactReadback::ContactReadback(SphTransfer& transfer, std::span<const Vec2> points) {
  if (transfer.def().normalisation != SphNormalisation::Shepard || transfer.channels() != 2)
    throw InvalidArgument("contact read-back: needs a two-channel Shepard transfer");
  const SphGrid probe(transfer.def().grid);
  (void)transfer.gather(probe, points);  // rebuilds S from the points (the cnn starter's path)
  const SphGrid& S = transfer.weights();
  const double min_weight = transfer.def().min_weight_ratio * transfer.kernel().peak();
  nx_ = S.nx();
  ny_ = S.ny();
  stencil_.reserve(points.size());
  weight_.reserve(points.size());
  for (const Vec2& q : points) {
    const BilinearStencil st = S.stencil(q);
    const double sw = S.apply(0, st);
    stencil_.push_back(st);
    weight_.push_back(sw > min_weight ? sw : 0.0);
  }
}

void ContactReadback::forward(const float* grid, std::span<double> out) const {
  if (out.size() != 2 * stencil_.size()) throw InvalidArgument("contact read-back: output size");
  const std::size_t P = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  for (std::size_t k = 0; k < stencil_.size(); ++k) {
    const BilinearStencil& s = stencil_[k];
    for (int c = 0; c < 2; ++c) {
      const float* ch = grid + static_cast<std::size_t>(c) * P;
      const float* r0 = ch + static_cast<std::size_t>(s.j0) * nx_;
      const float* r1 = ch + static_cast<std::size_t>(s.j1) * nx_;
      // SphGrid::apply's expression on the float grid promoted to double.
      const double v = (1.0 - s.fy) * ((1.0 - s.fx) * double(r0[s.i0]) + s.fx * double(r0[s.i1])) +
                       s.fy * ((1.0 - s.fx) * double(r1[s.i0]) + s.fx * double(r1[s.i1]));
      out[2 * k + static_cast<std::size_t>(c)] = weight_[k] > 0 ? v / weight_[k] : 0.0;
    }
  }
}

void ContactReadback::adjoint(std::span<const double> dout, float* dgrid) const {
  if (dout.size() != 2 * stencil_.size()) throw InvalidArgument("contact read-back: gradient size");
  const std::size_t P = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  for (std::size_t k = 0; k < stencil_.size(); ++k) {
    const BilinearStencil& s = stencil_[k];
    const double sw = weight_[k];
    if (sw == 0.0) continue;
    for (int c = 0; c < 2; ++c) {
      const double g = dout[2 * k + static_cast<std::size_t>(c)] / sw;
      float* ch = dgrid + static_cast<std::size_t>(c) * P;
      float* r0 = ch + static_cast<std::size_t>(s.j0) * nx_;
      float* r1 = ch + static_cast<std::size_t>(s.j1) * nx_;
      r0[s.i0] += static_cast<float>(g * s.w00());
      r0[s.i1] += static_cast<float>(g * s.w01());
      r1[s.i0] += static_cast<float>(g * s.w10());
      r1[s.i1] += static_cast<float>(g * s.w11());
    }
  }
}

}  // namespace dc
