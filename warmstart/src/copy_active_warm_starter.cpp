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
//   copy-active:normal, copy-active:friction  builtin-active's active set with only one half of
//                  λ*'s corrected: normal = which contacts touch (a contact λ* loads that
//                  builtin separates sticks; builtin's friction mode is kept where both touch),
//                  friction = the stick/slide mode where both touch. Is one half the hard part?
// These are dense, O(rows³): diagnostics for piles of a few hundred bodies (kMaxDenseDiagnosticRows).
//   copy-active-cg[:ITER], builtin-active-cg[:ITER]  the same two with the minimum-norm solve done
//                  matrix-free by ITER CGLS steps (default 100; solve_on_active_set_cgls): what
//                  the active-set route costs without the dense factorisation.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
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

/// Where an active-set starter takes its modes from.
struct ActiveSetSource {
  enum class Part { All, Normal, Friction };
  bool oracle = false;     ///< false: builtin-active; true: copy-active (corrected by λ*)
  double share = 1.0;      ///< F: the share of the wrong modes corrected (by key hash)
  Part part = Part::All;   ///< which half of λ*'s modes is used (copy-active:normal|friction)
  int cgls = 0;            ///< > 0: CGLS steps instead of the dense solve (the -cg starters)
};

class ActiveSetWarmStarter final : public WarmStarter {
 public:
  ActiveSetWarmStarter(ActiveSetSource src, std::string arg) : src_(src), arg_(std::move(arg)) {}
  std::string name() const override {
    std::string n = src_.oracle ? "copy-active" : "builtin-active";
    if (src_.cgls > 0) n += "-cg";
    return arg_.empty() ? n : n + ":" + arg_;
  }
  bool uses_oracle() const override { return src_.oracle; }
  double oracle_ms() const override { return oracle_ms_; }

  Eigen::VectorXd initial_guess(const StepView& v) override {
    const World& w = v.world;
    const Eigen::VectorXd base = builtin_guess(w);
    oracle_ms_ = 0;
    if (w.contacts().empty()) return base;
    std::vector<ContactMode> modes = remembered_modes(w, base);
    if (src_.oracle) {
      const Eigen::VectorXd star = step_oracle(v, oracle_ms_);
      for (std::size_t c = 0; c < modes.size(); ++c) {
        if (src_.share < 1 && !(key_share(w.contacts()[c].key) < src_.share)) continue;
        const ContactMode m = contact_mode(w.constraints(), static_cast<int>(c), star);
        const bool touches = m != ContactMode::Separating, touched = modes[c] != ContactMode::Separating;
        switch (src_.part) {
          case ActiveSetSource::Part::All: modes[c] = m; break;
          case ActiveSetSource::Part::Normal:
            if (!touches) modes[c] = m;
            else if (!touched) modes[c] = ContactMode::Sticking;
            break;
          case ActiveSetSource::Part::Friction:
            if (touches && touched) modes[c] = m;
            break;
        }
      }
    }
    const std::string who = name();
    return src_.cgls > 0 ? solve_on_active_set_cgls(w, base, modes, src_.cgls, who.c_str())
                         : solve_on_active_set(w, base, modes, who.c_str());
  }

 private:
  ActiveSetSource src_;
  std::string arg_;
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
  ActiveSetSource src;
  src.oracle = true;
  if (spec.arg == "normal") {
    src.part = ActiveSetSource::Part::Normal;
  } else if (spec.arg == "friction") {
    src.part = ActiveSetSource::Part::Friction;
  } else if (!spec.arg.empty()) {
    std::size_t used = 0;
    try {
      src.share = std::stod(spec.arg, &used);
    } catch (const std::logic_error&) {
      used = 0;
    }
    if (used != spec.arg.size() || !(src.share >= 0 && src.share <= 1))
      throw ConfigError("warm starter '" + spec.full() + "': expected copy-active[:F|:normal|:friction] with 0 <= F <= 1");
  }
  return std::make_unique<ActiveSetWarmStarter>(src, spec.arg);
}

std::unique_ptr<WarmStarter> make_builtin_active_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  reject_argument(spec);
  return std::make_unique<ActiveSetWarmStarter>(ActiveSetSource{}, "");
}

std::unique_ptr<WarmStarter> make_copy_active_cg_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  ActiveSetSource src;
  src.oracle = true;
  src.cgls = parse_cgls_iterations(spec);
  return std::make_unique<ActiveSetWarmStarter>(src, spec.arg);
}

std::unique_ptr<WarmStarter> make_builtin_active_cg_warm_starter(const WarmStartSpec& spec, const WarmStartEnv&) {
  ActiveSetSource src;
  src.cgls = parse_cgls_iterations(spec);
  return std::make_unique<ActiveSetWarmStarter>(src, spec.arg);
}

}  // namespace dc
