#pragma once
// Building blocks for writing a warm starter against this library: builtin's memory (the
// previous step's λ by contact key), the size limit of the dense diagnostics and the read-back
// of kernel-weighted gains. The starters of dc_warmstart and dc_research use them; a user's own
// starter may too. Its arguments are parsed with starter_argument.hpp (the options of this
// library's starters: starter_options.hpp).
#include <Eigen/Core>
#include <span>
#include <string>
#include <utility>

#include "dc/core/error.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {

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

}  // namespace dc
