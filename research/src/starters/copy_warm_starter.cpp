// copy[:D]: this step's λ*, solved beforehand to tight tolerance (the oracle, an upper
// bound on any predictor). copy:D rounds λ* to D decimals [N] to measure how sensitive
// PGS is to the accuracy of the guess. The oracle's cost is reported by oracle_ms().
// copy-noise:R multiplies every component by (1 + R·ξ), ξ ~ N(0, 1) drawn from the run's
// seed: the sweeps a predictor with relative error R would need (the accuracy a learned
// warm start has to reach to beat builtin; docs/bench.md).
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "dc/core/rng.hpp"
#include "dc/warmstart/oracle.hpp"
#include "oracle_starters.hpp"

namespace dc {
namespace {

class CopyWarmStarter final : public WarmStarter {
 public:
  explicit CopyWarmStarter(int decimals) : decimals_(decimals) {}
  /// Relative-noise variant (copy-noise:R).
  CopyWarmStarter(double relative_noise, std::string arg, std::uint64_t seed)
      : noise_(relative_noise), noise_arg_(std::move(arg)), rng_(seed) {}
  std::string name() const override {
    if (noise_ >= 0) return "copy-noise:" + noise_arg_;
    return decimals_ < 0 ? "copy" : "copy:" + std::to_string(decimals_);
  }
  bool uses_oracle() const override { return true; }
  double oracle_ms() const override { return oracle_ms_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    Eigen::VectorXd out = step_oracle(v, oracle_ms_);
    if (decimals_ >= 0) {
      const double scale = std::pow(10.0, decimals_);
      for (int i = 0; i < out.size(); ++i) out[i] = std::round(out[i] * scale) / scale;
      project_feasible(v.world.problem(), out);
    }
    if (noise_ >= 0) {
      for (int i = 0; i < out.size(); ++i) out[i] *= 1.0 + noise_ * rng_.gaussian(1.0);
      project_feasible(v.world.problem(), out);
    }
    return out;
  }

 private:
  int decimals_ = -1;   // −1: exact copy
  double noise_ = -1;   // < 0: no noise
  std::string noise_arg_;
  Rng rng_{1};
  double oracle_ms_ = 0;
};

}  // namespace

std::unique_ptr<WarmStarter> make_copy_noise_warm_starter(const WarmStartSpec& spec, const WarmStartEnv& env) {
  return std::make_unique<CopyWarmStarter>(parse_copy_noise_options(spec).relative, spec.arg, env.seed);
}

std::unique_ptr<WarmStarter> make_copy_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  const CopyStarterOptions o = parse_copy_options(spec);
  return std::make_unique<CopyWarmStarter>(o.rounded ? o.decimals : -1);
}

}  // namespace dc
