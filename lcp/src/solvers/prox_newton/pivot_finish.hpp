#pragma once
// prox-newton's pivoting finish for small frictional problems: the 2D Coulomb problem as a
// standard LCP (the split of Anitescu–Potra / Siconos' fc2d_tolcp) solved by Lemke's pivoting.
// Newton on the natural map converges to the active set it starts near; on a pile with more
// closed contacts than degrees of freedom that set can be one whose equations have no solution
// (too many sticking contacts) while another set (more of them sliding) has one. Lemke's
// complementary pivoting walks across sets and finds it. Unknowns, per normal row n and per
// friction row t coupled to n (λ_t = λ⁺ − λ⁻):
//     w_n  = A_nn λ_n + A_nt (λ⁺ − λ⁻) + b_n        ≥ 0  ⊥  λ_n ≥ 0
//     w⁺_t = A_tn λ_n + A_tt (λ⁺ − λ⁻) + b_t + β_t  ≥ 0  ⊥  λ⁺ ≥ 0
//     w⁻_t = −(A_tn λ_n + A_tt (λ⁺ − λ⁻) + b_t) + β_t ≥ 0 ⊥  λ⁻ ≥ 0
//     s_t  = μ_t λ_n − λ⁺ − λ⁻                      ≥ 0  ⊥  β_t ≥ 0   (β_t = −u_t when sliding)
// Scaled so entries are O(1): λ = (‖b‖∞ / max A_ii) λ', β = ‖b‖∞ β', rows divided by ‖b‖∞.
// Dense tableau of N = normal rows + 3·friction rows: O(N²) memory and per pivot.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::solvers::prox {

struct PivotOutcome {
  std::optional<Eigen::VectorXd> lambda;  ///< λ of the hard problem when Lemke ended on a solution
  int pivots = 0;
  std::string why;  ///< how the pivoting ended, or why it did not run
};

/// Size of the standard LCP for p (normal rows + 3·friction rows), or −1 when p has a row that
/// is neither a normal row (lo = 0, hi = ∞) nor a friction row coupled to one.
int pivot_lcp_size(const LcpProblem& p);

/// Lemke on the split LCP of p (assembled A), at most 50·N + 10 pivots.
PivotOutcome pivot_solve(const LcpProblem& p);

/// The rows of a local pivoting finish around λ: every contact with a row whose natural-map
/// residual |λ_i − mid(lo_i, λ_i − w_i, hi_i)| exceeds `threshold` [N] (the violators), then
/// `rings` times the contacts coupled to the set through A (sharing a body), each ring added
/// whole only while the set keeps at most `max_size` split-LCP unknowns. Ascending; empty when
/// there is no violator or p is not a contact problem (pivot_lcp_size < 0).
std::vector<int> local_pivot_rows(const LcpProblem& p, const Eigen::VectorXd& lambda, double threshold, int rings,
                                  int max_size);

/// Lemke on the subproblem of `rows` (closed under normal/friction coupling, ascending) with
/// every other row fixed at λ: A_SS λ_S + (b_S + A_{S,S̄} λ_S̄). On a Solved end, the returned
/// λ is the given one with λ_S replaced by Lemke's answer. On an active set that blocks Newton
/// (closed contacts that should open, sticking rows that should slide) the violators and their
/// neighbours are few, so this pivots on a tableau far smaller than the whole problem's.
/// With shift > 0 the subproblem is the proximal one around λ_S, (A_SS + δI) λ_S + (… − δ λ_S⁰),
/// δ = shift·max A_ii: its solution stays near λ_S⁰ where A_SS is singular (many contacts per
/// body), so the fixed rows' velocities move little.
PivotOutcome local_pivot_solve(const LcpProblem& p, const Eigen::VectorXd& lambda, const std::vector<int>& rows,
                               double shift);

}  // namespace dc::solvers::prox
