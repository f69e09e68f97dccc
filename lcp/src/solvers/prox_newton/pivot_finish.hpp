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

}  // namespace dc::solvers::prox
