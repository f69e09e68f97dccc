#pragma once
// The projected Gauss–Seidel / SOR sweep on the assembled sparse A (docs/design.md §2), shared by
// pgs-assembled (ω = 1), psor (any ω) and the PGS polish of the newton solver.
//
// Row i:  r_i = A_i·λ + b_i                         [m/s]
//         λ_i ← proj_[lo_i, hi_i](λ_i − ω r_i / A_ii)
// with the friction bounds ±μ λ_n evaluated at the current (already updated) normal value.
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "solvers/solver_common.hpp"

namespace dc::solvers {

class AssembledSweep {
 public:
  /// Copies A into compressed form if needed and precomputes 1/A_ii. Requires a
  /// validated problem.
  explicit AssembledSweep(const LcpProblem& p);

  /// One sweep in place; returns θ = max_i |Δλ_i|, sets nonfinite on a non-finite update.
  double sweep(Eigen::VectorXd& lambda, double omega, bool& nonfinite) const;

  /// Rows with A_ii ≤ 0 (handled by singular_row_update, never divided by).
  [[nodiscard]] const std::vector<int>& singular_rows() const { return singular_; }

 private:
  const LcpProblem& p_;
  SparseRowMatrix compressed_;       // only used when p.A is not compressed
  const SparseRowMatrix* A_ = nullptr;
  std::vector<double> inv_diag_;     // 1/A_ii, 0 for singular rows
  RowBounds bounds_;
  std::vector<int> singular_;
};

}  // namespace dc::solvers
