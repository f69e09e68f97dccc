#pragma once
// Learning-rate schedules (per epoch, epoch counted from 0) as strategy objects.
#include <memory>
#include <string>
#include <string_view>

namespace dc {

class LrSchedule {
 public:
  virtual ~LrSchedule() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  [[nodiscard]] virtual double rate(int epoch) const = 0;
};

/// lr(e) = lr0.
class ConstantLr final : public LrSchedule {
 public:
  explicit ConstantLr(double lr);
  [[nodiscard]] std::string name() const override { return "constant"; }
  [[nodiscard]] double rate(int) const override { return lr_; }

 private:
  double lr_;
};

/// lr(e) = lr0 · γ^⌊e / step⌋.
class StepLr final : public LrSchedule {
 public:
  StepLr(double lr, int step_epochs, double gamma);
  [[nodiscard]] std::string name() const override { return "step"; }
  [[nodiscard]] double rate(int epoch) const override;

 private:
  double lr_;
  int step_;
  double gamma_;
};

/// Cosine annealing: lr(e) = lr_min + (lr0 − lr_min)·(1 + cos(π·min(e, E)/E))/2 over E epochs.
class CosineLr final : public LrSchedule {
 public:
  CosineLr(double lr, int total_epochs, double lr_min = 0.0);
  [[nodiscard]] std::string name() const override { return "cosine"; }
  [[nodiscard]] double rate(int epoch) const override;

 private:
  double lr_;
  int total_;
  double min_;
};

/// "constant", "step" (step every max(1, E/3) epochs, γ = 0.1) or "cosine" (lr_min = lr0/100)
/// over E = total_epochs. Throws ConfigError for other names or lr ≤ 0.
std::unique_ptr<LrSchedule> make_lr_schedule(std::string_view name, double lr, int total_epochs);

}  // namespace dc
