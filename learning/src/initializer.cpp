#include "dc/learning/initializer.hpp"

#include <cmath>

#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"

namespace dc {

void HeNormal::fill(Tensor& weight, int fan_in, int /*fan_out*/, Rng& rng) const {
  if (fan_in <= 0) throw InvalidArgument("HeNormal: fan_in must be positive");
  const double sigma = std::sqrt(2.0 / fan_in);
  for (std::size_t i = 0; i < weight.size(); ++i) weight[i] = static_cast<float>(rng.gaussian(sigma));
}

void GlorotUniform::fill(Tensor& weight, int fan_in, int fan_out, Rng& rng) const {
  if (fan_in + fan_out <= 0) throw InvalidArgument("GlorotUniform: fan_in + fan_out must be positive");
  const double a = std::sqrt(6.0 / (fan_in + fan_out));
  for (std::size_t i = 0; i < weight.size(); ++i) weight[i] = static_cast<float>(rng.uniform(-a, a));
}

std::unique_ptr<Initializer> make_initializer(std::string_view name) {
  if (name == "he_normal") return std::make_unique<HeNormal>();
  if (name == "glorot_uniform" || name == "xavier_uniform") return std::make_unique<GlorotUniform>();
  throw ConfigError("init: unknown initialiser '" + std::string(name) +
                    "' (expected he_normal or glorot_uniform)");
}

}  // namespace dc
