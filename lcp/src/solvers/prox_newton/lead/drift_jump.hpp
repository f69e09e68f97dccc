#pragma once
// The lead stage's drift jump on degenerate problems (ProxNewtonDef::degenerate_drift_jumps).
// Where A is singular and w = Aλ + b has a part on the free rows outside A's range (a box pile
// whose closed contacts cannot all hold with the sticking friction they have), Gauss–Seidel
// sweeps drift along A's null space: λ moves by the same vector d every sweep while w stays as
// it is (the iteration for an inconsistent singular system diverges linearly). nncg's momentum
// restarts every sweep there (β = ‖Δf_k‖²/‖Δf_{k−1}‖² a hair above 1), so it is plain PGS. The
// hard residual sits on a plateau — a friction row at its bound lags its normal row's drift by
// μ|d_n| per sweep — until a row reaches a bound (a contact opens, a friction row leaves or
// meets its bound), which can take thousands of sweeps; then the row modes change and the
// sweeps converge or drift on another way. The jump goes there at once: λ + s d, with d the
// last sweep's change and s the sweeps until the first row meets a bound.
#include <Eigen/Core>
#include <optional>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::solvers::prox {

/// The jump from the last three sweeps' iterates λ_{k−2}, λ_{k−1}, λ_k: when their changes
/// d_{k−1}, d_k agree to `linearity` (‖d_k − d_{k−1}‖∞ ≤ linearity·‖d_k‖∞, d_k ≠ 0) and a row
/// meets a bound along λ_k + s d_k at some finite s ≥ 2 sweeps (fewer: the sweeps get there
/// themselves), λ_k + s d_k projected onto the bounds; nothing otherwise. w along the jump is
/// not checked: on box piles the jumps that reach the target soonest move w by more than the
/// hard residual (s‖A d_k‖∞ above it), so a bound on that would forbid them.
[[nodiscard]] std::optional<Eigen::VectorXd> drift_jump(const LcpProblem& p, const Eigen::VectorXd& before_last,
                                                        const Eigen::VectorXd& last, const Eigen::VectorXd& now,
                                                        double linearity);

/// The steps s > 0 along λ + s d until the first row of `p` meets a bound: a normal or fixed
/// row its lo or hi, a friction row ±μ λ_n (λ_n following d too). Rows already at or past a
/// bound and friction rows within one step's movement of theirs (riding it: the sweep clamps a
/// friction row at the bound of its normal row's value before the sweep) never count.
/// +∞ when none does.
[[nodiscard]] double drift_steps_to_bound(const LcpProblem& p, const Eigen::VectorXd& lambda, const Eigen::VectorXd& d);

}  // namespace dc::solvers::prox
