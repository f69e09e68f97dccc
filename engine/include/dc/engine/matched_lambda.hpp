#pragma once
// The builtin warm start's λ⁰ (the persistent-contact match of contact_match.hpp, the put of the
// matched λ, the projection onto the bounds) into storage the caller keeps.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <span>

#include "dc/engine/contact.hpp"
#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// out ← λ⁰ of `problem`, whose contacts are `current`: each contact's (λ_n, λ_t) of the contact
/// with the same key in `previous` (0 for a new one), then made feasible as project_feasible
/// does: the same numbers as a zero vector, the puts of for_each_matched_contact and
/// project_feasible. Both lists sorted by key (InvalidArgument as match_contacts_by_key
/// otherwise). `out` is resized to the problem's rows (its storage reused when the size stays).
void put_matched_lambda(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        Eigen::VectorXd& out);
/// The same into a KeptVector (its storage reallocated only past its capacity).
void put_matched_lambda(std::span<const Contact> previous, std::span<const Contact> current, const LcpProblem& problem,
                        KeptVector& out);

/// project_feasible on contact c's rows: its normal row (not a friction row), then its tangent
/// row, whose bounds read that normal row only. False when the rows are not so related (then
/// nothing is written). Inline: called once per contact.
inline bool project_contact_rows(const LcpProblem& p, int c, Eigen::Ref<Eigen::VectorXd> lambda) {
  const ContactConstraint& k = p.constraints[c];
  if (p.is_friction_row(k.normal_row) ||
      (k.tangent_row >= 0 && p.normal_row[static_cast<size_t>(k.tangent_row)] != k.normal_row))
    return false;
  double& n = lambda[k.normal_row];
  if (!std::isfinite(n)) n = 0.0;
  n = std::clamp(n, p.lo[k.normal_row], p.hi[k.normal_row]);
  if (k.tangent_row >= 0) {
    double& t = lambda[k.tangent_row];
    if (!std::isfinite(t)) t = 0.0;
    t = std::clamp(t, p.lower(k.tangent_row, lambda), p.upper(k.tangent_row, lambda));
  }
  return true;
}

}  // namespace dc
