// builtin: the previous step's solved λ of the contact with the same key, 0 for new
// contacts — the persistent-contact warm start of Box2D and of the theses' "built-in".
// Both contact lists are sorted by key, so matching is one merge pass, O(C).
#include "starters.hpp"

namespace dc {
namespace {

class BuiltinWarmStarter final : public WarmStarter {
 public:
  std::string name() const override { return "builtin"; }
  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const auto& cur = w.contacts();
    const auto& prev = w.previous_contacts();
    Eigen::VectorXd out = Eigen::VectorXd::Zero(w.problem().rows());
    std::size_t j = 0;
    for (std::size_t c = 0; c < cur.size(); ++c) {
      while (j < prev.size() && prev[j].key < cur[c].key) ++j;
      if (j < prev.size() && prev[j].key == cur[c].key) {
        out[w.normal_row(static_cast<int>(c))] = prev[j].lambda_n;
        if (w.has_friction_rows()) out[w.tangent_row(static_cast<int>(c))] = prev[j].lambda_t;
      }
    }
    project_feasible(w.problem(), out);
    return out;
  }
};

}  // namespace

std::unique_ptr<WarmStarter> make_builtin_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<BuiltinWarmStarter>();
}

}  // namespace dc
