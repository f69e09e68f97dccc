#pragma once
// Private: factories of the starters in this library (registered by default_warm_starters). Each
// parses its options with starter_options.hpp and builds its starter from them.
#include <memory>

#include "dc/warmstart/starter_options.hpp"
#include "dc/warmstart/starter_support.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

std::unique_ptr<WarmStarter> make_zero_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_builtin_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_prev_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
/// gate and gate-l2 (the norm is in the name: parse_gate_options).
std::unique_ptr<WarmStarter> make_gate_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_extrapolate_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_gain_extrapolate_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_statics_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_coarse_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_builtin_active_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_builtin_active_cg_warm_starter(const WarmStartSpec&, const WarmStartEnv&);

}  // namespace dc
