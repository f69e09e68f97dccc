#include "dc/cnn/contact_readback.hpp"

#include <string>

#include "dc/core/error.hpp"

namespace dc {

namespace {

void require_two_channel_shepard(const SphTransfer& transfer) {
  if (transfer.def().normalisation != SphNormalisation::Shepard || transfer.channels() != 2)
    throw InvalidArgument("contact read-back: needs a two-channel Shepard transfer");
}

}  // namespace

ContactReadback::ContactReadback(SphTransfer& transfer, std::span<const Vec2> points) {
  require_two_channel_shepard(transfer);
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

ContactReadback ContactReadback::gain(SphTransfer& transfer, std::span<const Vec2> points,
                                      std::span<const double> lambda_prev) {
  require_two_channel_shepard(transfer);
  if (lambda_prev.size() != 2 * points.size())
    throw InvalidArgument("contact read-back: " + std::to_string(lambda_prev.size()) + " lambda_prev values for " +
                          std::to_string(points.size()) + " points (expected 2 each)");
  std::vector<double> sq(lambda_prev.size());
  for (std::size_t k = 0; k < sq.size(); ++k) sq[k] = lambda_prev[k] * lambda_prev[k];
  const SphGrid& D = transfer.splat(points, sq);
  ContactReadback r;
  r.gain_ = true;
  r.nx_ = D.nx();
  r.ny_ = D.ny();
  r.stencil_.reserve(points.size());
  r.coef_.reserve(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const BilinearStencil st = D.stencil(points[k]);
    std::array<double, 8> cf{};
    for (int c = 0; c < 2; ++c) {
      const double d00 = st.w00() * D.at(c, st.j0, st.i0), d01 = st.w01() * D.at(c, st.j0, st.i1);
      const double d10 = st.w10() * D.at(c, st.j1, st.i0), d11 = st.w11() * D.at(c, st.j1, st.i1);
      const double den = d00 + d01 + d10 + d11;
      // den = 0: no load near q (λp = 0 here and around): no gain can act, v = 0.
      const double f = den > 0 ? lambda_prev[2 * k + static_cast<std::size_t>(c)] / den : 0.0;
      cf[4 * c + 0] = d00 * f;
      cf[4 * c + 1] = d01 * f;
      cf[4 * c + 2] = d10 * f;
      cf[4 * c + 3] = d11 * f;
    }
    r.stencil_.push_back(st);
    r.coef_.push_back(cf);
  }
  return r;
}

template <class T>
void ContactReadback::forward_impl(const T* grid, std::span<double> out) const {
  if (out.size() != 2 * stencil_.size()) throw InvalidArgument("contact read-back: output size");
  const std::size_t P = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  for (std::size_t k = 0; k < stencil_.size(); ++k) {
    const BilinearStencil& s = stencil_[k];
    for (int c = 0; c < 2; ++c) {
      const T* ch = grid + static_cast<std::size_t>(c) * P;
      const T* r0 = ch + static_cast<std::size_t>(s.j0) * nx_;
      const T* r1 = ch + static_cast<std::size_t>(s.j1) * nx_;
      double v = 0;
      if (gain_) {
        const double* a = coef_[k].data() + 4 * c;
        v = a[0] * double(r0[s.i0]) + a[1] * double(r0[s.i1]) + a[2] * double(r1[s.i0]) + a[3] * double(r1[s.i1]);
      } else {
        // SphGrid::apply's expression on the grid promoted to double.
        const double b = (1.0 - s.fy) * ((1.0 - s.fx) * double(r0[s.i0]) + s.fx * double(r0[s.i1])) +
                         s.fy * ((1.0 - s.fx) * double(r1[s.i0]) + s.fx * double(r1[s.i1]));
        v = weight_[k] > 0 ? b / weight_[k] : 0.0;
      }
      out[2 * k + static_cast<std::size_t>(c)] = v;
    }
  }
}

void ContactReadback::forward(const float* grid, std::span<double> out) const { forward_impl(grid, out); }
void ContactReadback::forward(const double* grid, std::span<double> out) const { forward_impl(grid, out); }

void ContactReadback::adjoint(std::span<const double> dout, float* dgrid) const {
  if (dout.size() != 2 * stencil_.size()) throw InvalidArgument("contact read-back: gradient size");
  const std::size_t P = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  for (std::size_t k = 0; k < stencil_.size(); ++k) {
    const BilinearStencil& s = stencil_[k];
    if (!gain_ && weight_[k] == 0.0) continue;
    for (int c = 0; c < 2; ++c) {
      const double g = dout[2 * k + static_cast<std::size_t>(c)] / (gain_ ? 1.0 : weight_[k]);
      const std::array<double, 4> shep{s.w00(), s.w01(), s.w10(), s.w11()};
      const double* a = gain_ ? coef_[k].data() + 4 * c : shep.data();
      float* ch = dgrid + static_cast<std::size_t>(c) * P;
      float* r0 = ch + static_cast<std::size_t>(s.j0) * nx_;
      float* r1 = ch + static_cast<std::size_t>(s.j1) * nx_;
      r0[s.i0] += static_cast<float>(g * a[0]);
      r0[s.i1] += static_cast<float>(g * a[1]);
      r1[s.i0] += static_cast<float>(g * a[2]);
      r1[s.i1] += static_cast<float>(g * a[3]);
    }
  }
}

}  // namespace dc
