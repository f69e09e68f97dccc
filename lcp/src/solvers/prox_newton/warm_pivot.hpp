#pragma once
// prox-newton's warm pivoting finish (ProxNewtonDef::warm_pivot_rows): Lemke's method on the
// whole split LCP (pivot_finish.hpp) started from the complementary basis an iterate suggests
// instead of from λ = 0. On impacts the best iterate of the Newton parts and nncg can differ
// from the solution in the modes of a few tens of rows (sliding rows that should stick, with a
// zero natural-map residual at the iterate: no local rule finds them), while the cold Lemke walks
// thousands of pivots from λ = 0. From the iterate's basis B the tableau is B⁻¹[ I | −M | −d | q ]
// with d chosen so that B⁻¹d = 1: z₀ = max(0, −min x_B) makes the basis feasible, and the
// pivots only have to repair the wrong modes. B's z part is M_SS (S = the split unknowns the
// iterate holds basic), so the start costs one dense LU of M_SS and products with it.
#include <Eigen/Core>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/prox_newton/pivot_finish.hpp"

namespace dc::solvers::prox {

/// The split-LCP unknowns the iterate λ holds basic (ascending): λ_n > w_n on normal rows, and on
/// friction rows λ⁺ / λ⁻ where they exceed their complements and the slip β = |u_t| of a contact
/// at its bound (|λ_t| ≥ μ λ_n, open contacts included) where it exceeds μλ_n − |λ_t| (zero
/// there). All values in the split LCP's scaling.
std::vector<int> warm_basis(const SplitLcp& sp, const LcpProblem& p, const Eigen::VectorXd& lambda);

/// Lemke on the split LCP of p (assembled A) from the basis warm_basis(λ), at most `cap` pivots.
/// No answer when the basis matrix M_SS is singular (its LU's reciprocal condition below 1e-14)
/// or Lemke does not end on a solution.
PivotOutcome warm_pivot_solve(const LcpProblem& p, const Eigen::VectorXd& lambda, int cap);

}  // namespace dc::solvers::prox
