// builtin-extrapolate: builtin with temporal linear extrapolation of each contact's λ.
// A contact with the same key in the last two steps gets λ⁰ = 2 λ^{t−1} − λ^{t−2} (the
// straight line through its last two values, one step on); one seen only in the last step
// gets λ^{t−1} (= builtin); a new one gets 0. The guess is then clamped into the feasible
// set (λ_n ≥ 0, |λ_t| ≤ μ λ_n: project_feasible). The memory of λ^{t−2} is the previous
// step's previous_contacts(), kept here; it is dropped when the world's step index does
// not advance by exactly one between calls (a different or restarted trajectory).
#include "starters.hpp"

namespace dc {
namespace {

class ExtrapolateWarmStarter final : public WarmStarter {
 public:
  std::string name() const override { return "builtin-extrapolate"; }
  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const auto& cur = w.contacts();
    const auto& prev = w.previous_contacts();
    Eigen::VectorXd out = Eigen::VectorXd::Zero(w.problem().rows());
    const bool history = last_step_ >= 0 && w.step_index() == last_step_ + 1;
    const std::vector<int> m1 = match_contacts_by_key(prev, cur);
    const std::vector<int> m2 = history ? match_contacts_by_key(older_, cur) : std::vector<int>(cur.size(), -1);
    for (std::size_t c = 0; c < cur.size(); ++c) {
      if (m1[c] < 0) continue;
      const Contact& p1 = prev[static_cast<std::size_t>(m1[c])];
      double ln = p1.lambda_n, lt = p1.lambda_t;
      if (m2[c] >= 0) {
        const Contact& p2 = older_[static_cast<std::size_t>(m2[c])];
        ln = 2 * p1.lambda_n - p2.lambda_n;
        lt = 2 * p1.lambda_t - p2.lambda_t;
      }
      w.constraints().put(static_cast<int>(c), ln, lt, out);
    }
    project_feasible(w.problem(), out);
    older_ = prev;
    last_step_ = w.step_index();
    return out;
  }

 private:
  std::vector<Contact> older_;  ///< previous_contacts() of the last call: λ^{t−2} now
  int last_step_ = -1;
};

}  // namespace

std::unique_ptr<WarmStarter> make_extrapolate_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<ExtrapolateWarmStarter>();
}

}  // namespace dc
