#include "dc/learning/optimizer.hpp"

#include "dc/core/error.hpp"

namespace dc {

Sgd::Sgd(SgdDef def) : def_(def) {
  if (!(def.momentum >= 0.0 && def.momentum < 1.0))
    throw InvalidArgument("Sgd: momentum must be in [0, 1), got " + std::to_string(def.momentum));
  if (!(def.weight_decay >= 0.0))
    throw InvalidArgument("Sgd: weight_decay must be >= 0, got " + std::to_string(def.weight_decay));
}

void Sgd::step(std::span<const ParamRef> params, double lr) {
  if (!(lr > 0.0)) throw InvalidArgument("Sgd::step: learning rate must be > 0, got " + std::to_string(lr));
  if (def_.momentum > 0.0 && velocity_.size() != params.size()) {
    velocity_.assign(params.size(), Eigen::VectorXf());
    for (std::size_t i = 0; i < params.size(); ++i) velocity_[i].setZero(static_cast<Eigen::Index>(params[i].value->size()));
  }
  const float flr = static_cast<float>(lr);
  const float mu = static_cast<float>(def_.momentum);
  for (std::size_t i = 0; i < params.size(); ++i) {
    const ParamRef& p = params[i];
    require_shape(p.grad->shape(), p.value->shape(), "Sgd::step " + p.name);
    auto w = p.value->flat();
    auto g = p.grad->flat();
    const float lambda = p.decay ? static_cast<float>(def_.weight_decay) : 0.0f;
    if (def_.momentum > 0.0) {
      Eigen::VectorXf& v = velocity_[i];
      if (v.size() != w.size()) throw InvalidArgument("Sgd::step: parameter list changed (" + p.name + ")");
      v = mu * v + g + lambda * w;
      w -= flr * v;
    } else {
      w -= flr * (g + lambda * w);
    }
  }
}

}  // namespace dc
