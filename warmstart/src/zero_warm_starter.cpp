// zero: λ⁰ = 0, the baseline ("none" in the theses).
#include "starters.hpp"

namespace dc {
namespace {

class ZeroWarmStarter final : public WarmStarter {
 public:
  std::string name() const override { return "zero"; }
  Eigen::VectorXd initial_guess(const StepView& v) override {
    return Eigen::VectorXd::Zero(v.world.problem().rows());
  }
};

}  // namespace

std::unique_ptr<WarmStarter> make_zero_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<ZeroWarmStarter>();
}

}  // namespace dc
