#include "dc/learning/mse_loss.hpp"

#include "dc/core/error.hpp"

namespace dc {

double MseLoss::operator()(const Tensor& pred, const Tensor& target, const Tensor* weight, Tensor* grad) const {
  require_shape(target.shape(), pred.shape(), "MseLoss target");
  const Shape& s = pred.shape();
  bool shared = false;  // one weight map shared by all channels
  if (weight != nullptr) {
    const Shape& ws = weight->shape();
    shared = ws.c == 1 && s.c != 1;
    if (!(ws == s) && !(shared && ws.n == s.n && ws.h == s.h && ws.w == s.w))
      throw InvalidArgument("MseLoss weight: shape " + ws.str() + " matches neither " + s.str() + " nor C = 1");
  }
  const std::size_t plane = s.plane();
  // w(i) for flat prediction index i = ((n·C + c)·H·W + q).
  auto w_at = [&](std::size_t i) -> double {
    if (weight == nullptr) return 1.0;
    if (!shared) return (*weight)[i];
    const std::size_t n = i / (plane * s.c);
    return (*weight)[n * plane + i % plane];
  };
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < pred.size(); ++i) {
    const double w = w_at(i);
    if (w < 0.0) throw InvalidArgument("MseLoss weight: negative weight at element " + std::to_string(i));
    const double e = static_cast<double>(pred[i]) - target[i];
    num += w * e * e;
    den += w;
  }
  if (grad != nullptr) {
    grad->resize(s);
    const double scale = den > 0.0 ? 2.0 / den : 0.0;
    for (std::size_t i = 0; i < pred.size(); ++i)
      (*grad)[i] = static_cast<float>(scale * w_at(i) * (static_cast<double>(pred[i]) - target[i]));
  }
  return den > 0.0 ? num / den : 0.0;
}

}  // namespace dc
