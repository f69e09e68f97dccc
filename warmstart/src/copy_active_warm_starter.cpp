// copy-active (oracle diagnostic) and builtin-active (no oracle): builtin, moved as little as
// possible to satisfy the LCP's equations on an active set — which contacts separate, which
// stick, which slide and in which direction — solved by solve_on_active_set
// (active_set_solve.cpp).
//
// Why: copy-range (copy_range_warm_starter.cpp) showed that what builtin lacks is the force
// redistribution in the null space of A that makes λ* satisfy its bounds. If the bounds act
// mainly through WHICH of them binds, the active set should recover most of it:
//   copy-active    takes the active set of this step's λ* (not its values): an oracle bound of
//                  a predictor of the active set;
//   builtin-active takes it from builtin's memory: a remembered contact keeps the mode of its
//                  previous λ; a new contact is touching and sticking when it is closing
//                  (gap ≤ [contact] slop + margin), separating otherwise.
// Both are dense, O(rows³): diagnostics for piles of a few hundred bodies (kMaxDenseDiagnosticRows).
#include <string>
#include <vector>

#include "active_set_solve.hpp"
#include "starters.hpp"

namespace dc {

namespace {

class ActiveSetWarmStarter final : public WarmStarter {
 public:
  explicit ActiveSetWarmStarter(bool oracle) : oracle_(oracle) {}
  std::string name() const override { return oracle_ ? "copy-active" : "builtin-active"; }
  bool uses_oracle() const override { return oracle_; }
  double oracle_ms() const override { return oracle_ms_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const Eigen::VectorXd base = builtin_guess(w);
    oracle_ms_ = 0;
    if (w.contacts().empty()) return base;
    const ContactConstraints& cons = w.constraints();
    const std::size_t n = w.contacts().size();
    std::vector<ContactMode> modes(n);
    if (oracle_) {
      const Eigen::VectorXd star = step_oracle(v, oracle_ms_);
      for (std::size_t c = 0; c < n; ++c) modes[c] = contact_mode(cons, static_cast<int>(c), star);
    } else {
      // Which contacts builtin remembers: the key match builtin itself uses.
      const std::vector<int> match = match_contacts_by_key(w.previous_contacts(), w.contacts());
      const double closing = w.def().contact.slop + w.def().contact.margin;
      for (std::size_t c = 0; c < n; ++c) {
        const int k = static_cast<int>(c);
        if (match[c] < 0)
          modes[c] = w.contacts()[c].gap <= closing ? ContactMode::Sticking : ContactMode::Separating;
        else
          modes[c] = contact_mode(cons, k, base);
      }
    }
    return solve_on_active_set(w, base, modes, oracle_ ? "copy-active" : "builtin-active");
  }

 private:
  bool oracle_;
  double oracle_ms_ = 0;
};

}  // namespace

std::unique_ptr<WarmStarter> make_copy_active_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<ActiveSetWarmStarter>(true);
}

std::unique_ptr<WarmStarter> make_builtin_active_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<ActiveSetWarmStarter>(false);
}

}  // namespace dc
