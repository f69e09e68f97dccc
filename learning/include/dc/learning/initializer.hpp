#pragma once
// Weight initialisers as small strategy objects. A layer calls fill() on its weight
// tensor with its fan-in / fan-out (conv: C_in·k², C_out·k²; dense: inputs, outputs).
#include <memory>
#include <string>
#include <string_view>

#include "dc/learning/tensor.hpp"

namespace dc {

class Rng;

class Initializer {
 public:
  virtual ~Initializer() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  virtual void fill(Tensor& weight, int fan_in, int fan_out, Rng& rng) const = 0;
};

/// He/Kaiming normal: w ~ N(0, 2/fan_in). Keeps activation variance constant through
/// ReLU layers (half of the units are zero, hence the factor 2). The default.
class HeNormal final : public Initializer {
 public:
  [[nodiscard]] std::string name() const override { return "he_normal"; }
  void fill(Tensor& weight, int fan_in, int fan_out, Rng& rng) const override;
};

/// Xavier/Glorot uniform: w ~ U(−a, a), a = √(6 / (fan_in + fan_out)); variance
/// 2/(fan_in+fan_out), balancing forward and backward signal for linear/tanh units.
class GlorotUniform final : public Initializer {
 public:
  [[nodiscard]] std::string name() const override { return "glorot_uniform"; }
  void fill(Tensor& weight, int fan_in, int fan_out, Rng& rng) const override;
};

/// "he_normal" or "glorot_uniform" (alias "xavier_uniform"); throws ConfigError otherwise.
std::unique_ptr<Initializer> make_initializer(std::string_view name);

}  // namespace dc
