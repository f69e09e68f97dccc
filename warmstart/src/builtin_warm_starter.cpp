// builtin: the previous step's solved λ of the contact with the same key, 0 for new
// contacts — the persistent-contact warm start of Box2D and of the theses' "built-in".
// Matching: put_matched_lambda (one merge pass over the key-sorted lists, O(C)).
#include "starters.hpp"

#include "dc/engine/contact_match.hpp"
#include "dc/engine/matched_lambda.hpp"

namespace dc {

void put_previous_lambda_by_key(const World& w, Eigen::VectorXd& out) {
  const auto& cur = w.contacts();
  const auto& prev = w.previous_contacts();
  const ContactConstraints& rows = w.constraints();
  for_each_matched_contact(prev, cur, [&](std::size_t c, const Contact& p) {
    rows.put(static_cast<int>(c), p.lambda_n, p.lambda_t, out);
  });
}

Eigen::VectorXd builtin_guess(const World& w) {
  Eigen::VectorXd out;
  put_matched_lambda(w.previous_contacts(), w.contacts(), w.problem(), out);
  return out;
}

namespace {

class BuiltinWarmStarter final : public WarmStarter {
 public:
  std::string name() const override { return "builtin"; }
  Eigen::VectorXd initial_guess(const StepView& v) override { return builtin_guess(v.world); }
  void initial_guess_into(const StepView& v, KeptVector& out) override { v.world.builtin_guess_into(out); }
};

}  // namespace

bool is_builtin_warm_starter(const WarmStarter& starter) {
  return dynamic_cast<const BuiltinWarmStarter*>(&starter) != nullptr;
}

std::unique_ptr<WarmStarter> make_builtin_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<BuiltinWarmStarter>();
}

}  // namespace dc
