#pragma once
// Private: factories of the oracle starters and negative controls (registered by
// add_research_starters), and the oracle they share. Each parses its options with
// oracle_starter_options.hpp (or dc_warmstart's starter_options.hpp) and builds its starter
// from them.
#include <Eigen/Core>
#include <chrono>
#include <memory>

#include "dc/research/oracle_starter_options.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/starter_support.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

/// This step's λ* for an oracle starter: the bench's (v.oracle) when it has one, else solved
/// here with solve_oracle; `ms` gets the time of that solve [ms] (0 when given).
inline Eigen::VectorXd step_oracle(const StepView& v, double& ms) {
  ms = 0;
  if (v.oracle) return *v.oracle;
  const auto t0 = std::chrono::steady_clock::now();
  Eigen::VectorXd star = solve_oracle(v.world.problem()).lambda;
  ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return star;
}

std::unique_ptr<WarmStarter> make_copy_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_copy_noise_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_copy_range_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_copy_active_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_copy_active_cg_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_residual_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_gain_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_gain_add_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_random_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_bad_warm_starter(const WarmStartSpec&, const WarmStartEnv&);

}  // namespace dc
