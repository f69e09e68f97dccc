#pragma once
// The natural map of the box-friction LCP and its generalised Newton linearisation, the
// pieces newton-sparse iterates with (docs/solvers.md "newton-sparse").
//
//   H_i(λ) = λ_i − mid(lo_i(λ), λ_i − w_i, hi_i(λ)),  w = A λ + b,
//   friction rows: lo = −μ max(0, λ_n), hi = μ max(0, λ_n)   (n = normal_row[i]).
//
// Row modes at λ, with y_i = λ_i − w_i:
//   free      lo < y < hi:  H_i = w_i,               Newton row  A_i·Δ = −w_i
//   at upper  y ≥ hi:       H_i = λ_i − hi_i(λ),     Newton row  Δ_i − μ[λ_n>0] Δ_n = −H_i
//   at lower  y ≤ lo:       H_i = λ_i − lo_i(λ),     Newton row  Δ_i + μ[λ_n>0] Δ_n = −H_i
// (fixed-bound rows have no Δ_n term). A clamped row therefore moves by
//   Δ_i = d_i + s_i Δ_n,   d_i = −H_i (+ s_i d_n when its normal row is clamped too),
// and only a clamped friction row whose normal row is free keeps a term in the unknowns:
// the "coupling" s_i = ±μ (sliding friction follows its normal force).
#include <Eigen/Core>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::solvers {

/// H and w at one λ, with the two norms the solver uses.
struct NaturalMapValue {
  Eigen::VectorXd w;  ///< A λ + b [m/s]
  Eigen::VectorXd h;  ///< H(λ) [N]
  double max_abs = 0; ///< ‖H‖∞ [N] (+∞ when not finite)
  double merit = 0;   ///< ½‖s·H‖², summed in row order (+∞ when not finite)
};

/// Evaluates w and H at λ with the assembled A (p.A must be present). `scale` s > 0 keeps the
/// merit ½‖s·H‖² finite for huge entries (newton-sparse uses s = 1/max(1, ‖b‖∞) per solve).
void evaluate_natural_map(const LcpProblem& p, const Eigen::VectorXd& lambda, double scale, NaturalMapValue& out);

/// Projects λ onto its bounds: fixed rows onto [lo, hi], then friction rows onto ±μ max(0, λ_n).
void project_onto_bounds(const LcpProblem& p, Eigen::VectorXd& lambda);

/// A clamped friction row whose normal row is free: Δ_row = d_row + slope·Δ_normal.
struct FrictionCoupling {
  int row;
  int normal;
  double slope;  ///< ±μ
};

/// The Newton linearisation at λ.
struct NewtonLinearization {
  std::vector<char> free;                ///< 1 for free rows
  Eigen::VectorXd known;                 ///< d on clamped rows, 0 on free rows [N]
  std::vector<FrictionCoupling> couplings;
  int free_count = 0;
};

/// Classifies the rows at λ (value = evaluate_natural_map at λ) and fills the known moves.
void linearize(const LcpProblem& p, const Eigen::VectorXd& lambda, const NaturalMapValue& value,
               NewtonLinearization& lin);

}  // namespace dc::solvers
