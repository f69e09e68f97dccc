#include "dc/learning/lr_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "dc/core/error.hpp"

namespace dc {

namespace {
void check_lr(double lr) {
  if (!(lr > 0.0) || !std::isfinite(lr)) throw InvalidArgument("learning rate must be positive, got " + std::to_string(lr));
}
}  // namespace

ConstantLr::ConstantLr(double lr) : lr_(lr) { check_lr(lr); }

StepLr::StepLr(double lr, int step_epochs, double gamma) : lr_(lr), step_(step_epochs), gamma_(gamma) {
  check_lr(lr);
  if (step_epochs < 1) throw InvalidArgument("StepLr: step must be >= 1 epoch");
  if (!(gamma > 0.0 && gamma <= 1.0)) throw InvalidArgument("StepLr: gamma must be in (0, 1]");
}

double StepLr::rate(int epoch) const { return lr_ * std::pow(gamma_, std::max(epoch, 0) / step_); }

CosineLr::CosineLr(double lr, int total_epochs, double lr_min) : lr_(lr), total_(total_epochs), min_(lr_min) {
  check_lr(lr);
  if (total_epochs < 1) throw InvalidArgument("CosineLr: total epochs must be >= 1");
  if (!(lr_min >= 0.0 && lr_min <= lr)) throw InvalidArgument("CosineLr: lr_min must be in [0, lr]");
}

double CosineLr::rate(int epoch) const {
  const double e = std::clamp(epoch, 0, total_);
  return min_ + (lr_ - min_) * 0.5 * (1.0 + std::cos(std::numbers::pi * e / total_));
}

std::unique_ptr<LrSchedule> make_lr_schedule(std::string_view name, double lr, int total_epochs) {
  try {
    if (name == "constant") return std::make_unique<ConstantLr>(lr);
    if (name == "step") return std::make_unique<StepLr>(lr, std::max(1, total_epochs / 3), 0.1);
    if (name == "cosine") return std::make_unique<CosineLr>(lr, std::max(1, total_epochs), lr / 100.0);
  } catch (const InvalidArgument& e) {
    throw ConfigError(std::string("lr schedule '") + std::string(name) + "': " + e.what());
  }
  throw ConfigError("lr schedule: unknown '" + std::string(name) + "' (expected constant, step or cosine)");
}

}  // namespace dc
