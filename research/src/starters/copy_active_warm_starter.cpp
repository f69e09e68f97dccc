// copy-active (oracle diagnostic): builtin-active's guess (active_set_solve.hpp) on the active
// set of this step's λ* instead of builtin's remembered one: the bound of an active-set
// predictor (docs/bench.md, docs/research.md "How complete the active set must be").
//   copy-active:F  builtin-active's set with a share F ∈ [0, 1] of its disagreements with λ*
//                  corrected, chosen by u(hash of contact key) < F: nested in F, same every run.
//   copy-active:normal, :friction  only which contacts touch, or only the stick/slide mode
//                  where both touch, taken from λ*.
//   copy-active-cg[:ITER]  the minimum-norm solve by ITER CGLS steps (default 100), matrix-free.
// The dense variants are O(rows³), refused above kMaxDenseDiagnosticRows.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "dc/warmstart/active_set_solve.hpp"
#include "oracle_starters.hpp"

namespace dc {

namespace {

/// u(key) ∈ [0, 1): splitmix64 of the packed key and feature, a fixed pseudo-random share.
double key_share(const ContactKey& k) {
  std::uint64_t z = k.packed() ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.feature)) * 0x9e3779b97f4a7c15ULL);
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

class CopyActiveWarmStarter final : public WarmStarter {
 public:
  /// cgls > 0: that many CGLS steps instead of the dense solve (copy-active-cg, which
  /// corrects every mode: default `options`).
  CopyActiveWarmStarter(CopyActiveOptions options, int cgls, std::string arg)
      : opt_(options), cgls_(cgls), arg_(std::move(arg)) {}
  std::string name() const override {
    const std::string n = cgls_ > 0 ? "copy-active-cg" : "copy-active";
    return arg_.empty() ? n : n + ":" + arg_;
  }
  bool uses_oracle() const override { return true; }
  double oracle_ms() const override { return oracle_ms_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const Eigen::VectorXd base = builtin_guess(w);
    oracle_ms_ = 0;
    if (w.contacts().empty()) return base;
    std::vector<ContactMode> modes = remembered_modes(w, base);
    const Eigen::VectorXd star = step_oracle(v, oracle_ms_);
    for (std::size_t c = 0; c < modes.size(); ++c) {
      if (opt_.share < 1 && !(key_share(w.contacts()[c].key) < opt_.share)) continue;
      const ContactMode m = contact_mode(w.constraints(), static_cast<int>(c), star);
      const bool touches = m != ContactMode::Separating, touched = modes[c] != ContactMode::Separating;
      switch (opt_.part) {
        case ActiveSetPart::All: modes[c] = m; break;
        case ActiveSetPart::Normal:
          if (!touches) modes[c] = m;
          else if (!touched) modes[c] = ContactMode::Sticking;
          break;
        case ActiveSetPart::Friction:
          if (touches && touched) modes[c] = m;
          break;
      }
    }
    const std::string who = name();
    return cgls_ > 0 ? solve_on_active_set_cgls(w, base, modes, cgls_, who.c_str())
                     : solve_on_active_set(w, base, modes, who.c_str());
  }

 private:
  CopyActiveOptions opt_;
  int cgls_;
  std::string arg_;
  double oracle_ms_ = 0;
};

}  // namespace

std::unique_ptr<WarmStarter> make_copy_active_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return std::make_unique<CopyActiveWarmStarter>(parse_copy_active_options(spec), 0, spec.arg);
}

std::unique_ptr<WarmStarter> make_copy_active_cg_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return std::make_unique<CopyActiveWarmStarter>(CopyActiveOptions{}, parse_cgls_options(spec).iterations, spec.arg);
}

}  // namespace dc
