// builtin-active and builtin-active-cg (no oracle): builtin, moved as little as possible to
// satisfy the LCP's equations on the active set builtin remembers — which contacts separate,
// which stick, which slide and in which direction (remembered_modes) — solved densely by
// solve_on_active_set or matrix-free by ITER CGLS steps (solve_on_active_set_cgls;
// active_set_solve.cpp).
//
// Why: copy-range (a research diagnostic) showed that what builtin lacks is the force
// redistribution in the null space of A that makes λ* satisfy its bounds; if the bounds act
// mainly through WHICH of them binds, the active set should recover most of it. The oracle
// counterpart copy-active (dc_research) takes the active set of this step's λ* instead.
// The dense solve is O(rows³): for piles of a few hundred bodies (kMaxDenseDiagnosticRows).
#include <string>
#include <utility>
#include <vector>

#include "dc/warmstart/active_set_solve.hpp"
#include "starters.hpp"

namespace dc {

namespace {

class BuiltinActiveWarmStarter final : public WarmStarter {
 public:
  /// cgls > 0: that many CGLS steps instead of the dense solve (builtin-active-cg).
  BuiltinActiveWarmStarter(int cgls, std::string arg) : cgls_(cgls), arg_(std::move(arg)) {}
  std::string name() const override {
    const std::string n = cgls_ > 0 ? "builtin-active-cg" : "builtin-active";
    return arg_.empty() ? n : n + ":" + arg_;
  }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const Eigen::VectorXd base = builtin_guess(w);
    if (w.contacts().empty()) return base;
    const std::vector<ContactMode> modes = remembered_modes(w, base);
    const std::string who = name();
    return cgls_ > 0 ? solve_on_active_set_cgls(w, base, modes, cgls_, who.c_str())
                     : solve_on_active_set(w, base, modes, who.c_str());
  }

 private:
  int cgls_;
  std::string arg_;
};

}  // namespace

std::unique_ptr<WarmStarter> make_builtin_active_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<BuiltinActiveWarmStarter>(0, "");
}

std::unique_ptr<WarmStarter> make_builtin_active_cg_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return std::make_unique<BuiltinActiveWarmStarter>(parse_cgls_options(spec).iterations, spec.arg);
}

}  // namespace dc
