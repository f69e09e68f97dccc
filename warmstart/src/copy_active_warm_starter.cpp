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
//   copy-active:F  builtin-active's active set with a share F ∈ [0, 1] of the contacts where it
//                  disagrees with λ*'s corrected to λ*'s mode: how well must a predictor of the
//                  mode CHANGES be to pay (F = 0 is builtin-active, F = 1 copy-active). Which
//                  contacts are corrected is fixed by a hash of the contact key, u(key) < F, so
//                  the corrected set grows with F (nested) and is the same in every run.
// These are dense, O(rows³): diagnostics for piles of a few hundred bodies (kMaxDenseDiagnosticRows).
//   copy-active-cg[:ITER], builtin-active-cg[:ITER]  the same two with the minimum-norm solve done
//                  matrix-free by ITER CGLS steps (default 100; solve_on_active_set_cgls): what
//                  the active-set route costs without the dense factorisation.
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "active_set_solve.hpp"
#include "starters.hpp"

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

/// builtin-active's active set: a remembered contact keeps the mode of builtin's λ (`base`); a
/// new one sticks when closing (gap ≤ slop + margin) and separates otherwise.
std::vector<ContactMode> remembered_modes(const World& w, const Eigen::VectorXd& base) {
  const std::size_t n = w.contacts().size();
  std::vector<ContactMode> modes(n);
  const std::vector<int> match = match_contacts_by_key(w.previous_contacts(), w.contacts());
  const double closing = w.def().contact.slop + w.def().contact.margin;
  for (std::size_t c = 0; c < n; ++c) {
    if (match[c] < 0)
      modes[c] = w.contacts()[c].gap <= closing ? ContactMode::Sticking : ContactMode::Separating;
    else
      modes[c] = contact_mode(w.constraints(), static_cast<int>(c), base);
  }
  return modes;
}

class ActiveSetWarmStarter final : public WarmStarter {
 public:
  /// known < 0: builtin-active (no oracle); otherwise the share F of copy-active:F.
  /// cgls > 0: that many CGLS steps instead of the dense solve (the -cg starters).
  ActiveSetWarmStarter(double known, std::string arg, int cgls = 0)
      : known_(known), arg_(std::move(arg)), cgls_(cgls) {}
  std::string name() const override {
    std::string n = known_ < 0 ? "builtin-active" : "copy-active";
    if (cgls_ > 0) n += "-cg";
    return arg_.empty() ? n : n + ":" + arg_;
  }
  bool uses_oracle() const override { return known_ >= 0; }
  double oracle_ms() const override { return oracle_ms_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const Eigen::VectorXd base = builtin_guess(w);
    oracle_ms_ = 0;
    if (w.contacts().empty()) return base;
    const std::size_t n = w.contacts().size();
    std::vector<ContactMode> modes;
    if (known_ >= 1) {
      modes.resize(n);  // copy-active: no need for builtin's modes
    } else {
      modes = remembered_modes(w, base);
    }
    if (known_ >= 0) {
      const Eigen::VectorXd star = step_oracle(v, oracle_ms_);
      for (std::size_t c = 0; c < n; ++c)
        if (known_ >= 1 || key_share(w.contacts()[c].key) < known_)
          modes[c] = contact_mode(w.constraints(), static_cast<int>(c), star);
    }
    const std::string who = name();
    return cgls_ > 0 ? solve_on_active_set_cgls(w, base, modes, cgls_, who.c_str())
                     : solve_on_active_set(w, base, modes, who.c_str());
  }

 private:
  double known_;
  std::string arg_;
  int cgls_;
  double oracle_ms_ = 0;
};

/// ITER of the -cg starters: a positive integer, 100 when absent.
int parse_cgls_iterations(const WarmStartSpec& spec) {
  if (spec.arg.empty()) return 100;
  std::size_t used = 0;
  int it = 0;
  try {
    it = std::stoi(spec.arg, &used);
  } catch (const std::logic_error&) {
    used = 0;
  }
  if (used != spec.arg.size() || it < 1)
    throw ConfigError("warm starter '" + spec.full() + "': expected " + spec.name + "[:ITER] with ITER >= 1");
  return it;
}

}  // namespace

std::unique_ptr<WarmStarter> make_copy_active_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  double share = 1.0;
  if (!spec.arg.empty()) {
    std::size_t used = 0;
    try {
      share = std::stod(spec.arg, &used);
    } catch (const std::logic_error&) {
      used = 0;
    }
    if (used != spec.arg.size() || !(share >= 0 && share <= 1))
      throw ConfigError("warm starter '" + spec.full() + "': expected copy-active[:F] with 0 <= F <= 1");
  }
  return std::make_unique<ActiveSetWarmStarter>(share, spec.arg);
}

std::unique_ptr<WarmStarter> make_builtin_active_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<ActiveSetWarmStarter>(-1.0, "");
}

std::unique_ptr<WarmStarter> make_copy_active_cg_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return std::make_unique<ActiveSetWarmStarter>(1.0, spec.arg, parse_cgls_iterations(spec));
}

std::unique_ptr<WarmStarter> make_builtin_active_cg_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  return std::make_unique<ActiveSetWarmStarter>(-1.0, spec.arg, parse_cgls_iterations(spec));
}

}  // namespace dc
