#pragma once
// Private: factories of the starters in this library (registered by default_warm_starters).
#include <chrono>
#include <span>
#include <string>
#include <utility>

#include "dc/engine/error.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

inline void reject_argument(const WarmStartSpec& spec) {
  if (!spec.arg.empty())
    throw ConfigError("warm starter '" + spec.name + "' takes no argument (got '" + spec.full() + "')");
}

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

/// Rows above which the dense O(rows³) diagnostics (copy-range, copy-active, builtin-active)
/// refuse a problem.
inline constexpr int kMaxDenseDiagnosticRows = 3000;

/// Throws InvalidArgument, naming `who`, when p has no Jacobian or more than
/// kMaxDenseDiagnosticRows rows.
inline void require_dense_diagnostic_size(const LcpProblem& p, const char* who) {
  if (!p.has_jacobian()) throw InvalidArgument(std::string(who) + ": the problem has no Jacobian");
  if (p.rows() > kMaxDenseDiagnosticRows)
    throw InvalidArgument(std::string(who) + ": " + std::to_string(p.rows()) + " rows exceed the dense diagnostic's limit of " +
                          std::to_string(kMaxDenseDiagnosticRows));
}

/// The kernel-weighted least-squares gains (ĝ_n, ĝ_t) = (N_n/D_n, N_t/D_t) of point c in a
/// four-field read-back (N_n, N_t, D_n, D_t per point; sph-gain and builtin-gain-extrapolate),
/// 0 where D = 0 (no load nearby).
inline std::pair<double, double> read_gains(std::span<const double> back, std::size_t c) {
  const double* f = back.data() + 4 * c;
  return {f[2] > 0 ? f[0] / f[2] : 0.0, f[3] > 0 ? f[1] / f[3] : 0.0};
}

/// builtin's memory: overwrites in `out` the rows of every current contact of `w` whose key
/// the previous step had with that contact's solved (λ_n, λ_t); other rows keep their value
/// (0 for builtin, the statics guess for builtin-statics). Defined in builtin_warm_starter.cpp.
void put_previous_lambda_by_key(const World& w, Eigen::VectorXd& out);

/// builtin's λ⁰ for w's current step: put_previous_lambda_by_key on zeros, projected
/// (the builtin starter's guess; the gate's fallback).
Eigen::VectorXd builtin_guess(const World& w);

std::unique_ptr<WarmStarter> make_zero_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_builtin_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_copy_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_copy_noise_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_random_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_bad_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_prev_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_residual_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_gain_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_sph_gain_add_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_gate_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_gate_l2_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_extrapolate_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_gain_extrapolate_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_statics_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_coarse_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_copy_range_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_copy_active_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_builtin_active_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_copy_active_cg_warm_starter(const WarmStartSpec&, const WarmStartEnv&);
std::unique_ptr<WarmStarter> make_builtin_active_cg_warm_starter(const WarmStartSpec&, const WarmStartEnv&);

}  // namespace dc
