#pragma once
// Optimisers as strategy objects. step() applies one update to every parameter from its
// gradient; state (momentum buffers) is keyed by the parameter's position in the list,
// so the same list (Network::parameters()) must be passed every step.
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "dc/learning/layers/layer.hpp"

namespace dc {

class Optimizer {
 public:
  virtual ~Optimizer() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  /// One update with learning rate lr (> 0).
  virtual void step(std::span<const ParamRef> params, double lr) = 0;
  /// Forget any state (momentum).
  virtual void reset() = 0;
};

/// SGD with optional (heavy-ball) momentum μ and L2 weight decay λ (PyTorch's convention):
///   g ← ∇L + λ·w   (only for ParamRef::decay parameters, i.e. weights, not biases)
///   v ← μ·v + g,   w ← w − lr·v          (μ = 0: plain SGD, w ← w − lr·g)
/// λ·w is the gradient of (λ/2)‖w‖² added to the loss.
struct SgdDef {
  double momentum = 0.0;      ///< μ ∈ [0, 1)
  double weight_decay = 0.0;  ///< λ ≥ 0
};

class Sgd final : public Optimizer {
 public:
  /// Throws InvalidArgument for μ ∉ [0, 1) or λ < 0.
  explicit Sgd(SgdDef def = {});
  [[nodiscard]] std::string name() const override { return "sgd"; }
  void step(std::span<const ParamRef> params, double lr) override;
  void reset() override { velocity_.clear(); }
  /// Momentum buffers, one per parameter in list order (empty before the first step or
  /// without momentum). For checkpointing: set_velocity() of a saved value makes the next
  /// step() continue exactly as the saved run would have.
  [[nodiscard]] const std::vector<Eigen::VectorXf>& velocity() const { return velocity_; }
  void set_velocity(std::vector<Eigen::VectorXf> v) { velocity_ = std::move(v); }

 private:
  SgdDef def_;
  std::vector<Eigen::VectorXf> velocity_;
};

}  // namespace dc
