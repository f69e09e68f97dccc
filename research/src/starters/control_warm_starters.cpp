// Negative controls of the theses: random and bad guesses, to show that a poor warm start
// costs sweeps (and that the bench can tell).
//   random:  λ_n ~ U(0, 5)·s,  λ_t ~ U(−2, 2)·s (then clamped to the friction cone)
//   bad:     λ_n = 50·s, λ_t = 0
// with the scene scale s = mean body weight m̄·|g| [N], so the controls mean the same on
// scaled scenes. random:SEED overrides the run's seed.
#include <cstdint>
#include <numeric>

#include "dc/core/rng.hpp"
#include "oracle_starters.hpp"

namespace dc {
namespace {

double scene_force_scale(const World& w) {
  const auto& m = w.bodies().mass;
  if (m.empty()) return 1.0;
  const double mean_mass = std::accumulate(m.begin(), m.end(), 0.0) / static_cast<double>(m.size());
  const double g = length(w.def().world.gravity);
  return mean_mass * (g > 0 ? g : 9.81);
}

class RandomWarmStarter final : public WarmStarter {
 public:
  explicit RandomWarmStarter(std::uint64_t seed) : rng_(seed) {}
  std::string name() const override { return "random"; }
  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const double s = scene_force_scale(w);
    Eigen::VectorXd out(w.problem().rows());
    for (const ContactConstraint& k : w.constraints()) {  // λ_t drawn only for rows that exist
      out[k.normal_row] = rng_.uniform(0.0, 5.0) * s;
      if (k.has_friction()) out[k.tangent_row] = rng_.uniform(-2.0, 2.0) * s;
    }
    project_feasible(w.problem(), out);
    return out;
  }

 private:
  Rng rng_;
};

class BadWarmStarter final : public WarmStarter {
 public:
  std::string name() const override { return "bad"; }
  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    Eigen::VectorXd out = Eigen::VectorXd::Zero(w.problem().rows());
    const double s = 50.0 * scene_force_scale(w);
    for (const ContactConstraint& k : w.constraints()) out[k.normal_row] = s;
    return out;
  }
};

}  // namespace

std::unique_ptr<WarmStarter> make_random_warm_starter(const WarmStartSpec& spec, const WarmStartEnv& env) {
  return std::make_unique<RandomWarmStarter>(parse_random_options(spec).seed.value_or(env.seed));
}

std::unique_ptr<WarmStarter> make_bad_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<BadWarmStarter>();
}

}  // namespace dc
