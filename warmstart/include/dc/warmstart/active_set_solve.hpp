#pragma once
// The LCP solved on a GIVEN active set — the solve of copy-active (the active set of
// λ*, an oracle diagnostic) and builtin-active (builtin's remembered active set, no oracle).
// contact_mode also picks builtin-coarse's loaded rows. Formulas in active_set_solve.cpp.
#include <Eigen/Core>
#include <vector>

#include "dc/engine/world.hpp"

namespace dc {

/// Which bound binds at a contact.
enum class ContactMode {
  Separating,   ///< λ_n = λ_t = 0
  Sticking,     ///< λ_n > 0, |λ_t| < μ λ_n: w_n = 0 and w_t = 0
  SlidingPlus,  ///< λ_n > 0, λ_t = +μ λ_n: w_n = 0
  SlidingMinus  ///< λ_n > 0, λ_t = −μ λ_n: w_n = 0
};

/// The mode of contact c in λ (per the rules above; |λ_t| ≥ μ λ_n (1 − 1e-9) counts as sliding).
ContactMode contact_mode(const ContactConstraints& cons, int c, const Eigen::VectorXd& lambda);

/// builtin-active's active set for w's current step: a contact remembered from the previous
/// step keeps the mode of builtin's λ (`base`, e.g. builtin_guess(w)); a new one sticks when
/// it is closing (gap ≤ [contact] slop + margin) and separates otherwise.
std::vector<ContactMode> remembered_modes(const World& w, const Eigen::VectorXd& base);

/// Relative pivot threshold below which solve_on_active_set treats a direction of S A L as
/// null (|pivot| ≤ threshold · |largest pivot|).
inline constexpr double kActiveSetRankThreshold = 1e-10;

/// The minimum-norm least-squares solution of M y = rhs, pivots below `threshold` (relative to
/// the largest) counted as zero: a complete orthogonal decomposition. Deterministic: it reads
/// no memory the decomposition did not write (see the .cpp for the trap).
Eigen::VectorXd min_norm_solve(const Eigen::MatrixXd& M, const Eigen::VectorXd& rhs, double threshold);

/// The guess nearest `base` (in the free variables) that satisfies the LCP's equations on the
/// active set `modes` (one per contact of w's current step), projected into the bounds.
/// Dense, O(rows³); throws InvalidArgument (naming `who`) without a Jacobian or above
/// kMaxDenseDiagnosticRows rows (starters.hpp).
Eigen::VectorXd solve_on_active_set(const World& w, const Eigen::VectorXd& base,
                                    const std::vector<ContactMode>& modes, const char* who);

/// The same guess with the minimum-norm solve done matrix-free: `iterations` CGLS steps on
/// S A L y = −S (A L x_b + b) from y = 0 (two A products each, O(nnz J); no size limit), then
/// projected. Tends to solve_on_active_set's answer as iterations grow; CGLS converges at the
/// rate of cond(S A L)², so a pile needs many. Throws InvalidArgument without a Jacobian.
Eigen::VectorXd solve_on_active_set_cgls(const World& w, const Eigen::VectorXd& base,
                                         const std::vector<ContactMode>& modes, int iterations, const char* who);

}  // namespace dc
