#pragma once
// Private to the solver family: one sweep of the matrix-free projected Gauss–Seidel of "pgs"
// (kernels, segments and their cost model: pgs_matrix_free.cpp) as an object, so that "nncg"
// (nncg.cpp) runs the identical sweep and adds its momentum between sweeps. Not public API.
//
// The sweep works on λ and on the body-velocity change Δu = M⁻¹ Jᵀ λ Δt (3 entries per body,
// then a "zero" body that is never written and a "sink" body that is never read; see the cost
// model). After any change δ of λ outside a sweep, the caller must add M⁻¹ J_iᵀ Δt δ_i to Δu
// (Δu is linear in λ) so that the invariant holds for the next sweep.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::solvers {

struct MatrixFreeRows;  // the packed rows and their segments (pgs_matrix_free.cpp)

class MatrixFreeSweep {
 public:
  MatrixFreeSweep();
  ~MatrixFreeSweep();
  MatrixFreeSweep(const MatrixFreeSweep&) = delete;
  MatrixFreeSweep& operator=(const MatrixFreeSweep&) = delete;

  /// Packs the rows of a validated problem with J into the kernels' segments (two-point
  /// manifolds as 2 × 2 blocks when `block_manifolds`). Returns "" on success, otherwise why
  /// the matrix-free form does not apply (a row of J on a third body).
  std::string prepare(const LcpProblem& p, bool block_manifolds);

  /// Δu = M⁻¹ Jᵀ λ Δt for `lambda`, followed by the zero and the sink body (6 zeros): the
  /// buffer `sweep` reads and writes. Its first body_entries() entries are the bodies'.
  [[nodiscard]] std::vector<double> velocity_change(const LcpProblem& p, const Eigen::VectorXd& lambda) const;

  /// 3 · bodies.
  [[nodiscard]] int body_entries() const;

  /// One Gauss–Seidel sweep over every row in place; returns θ = max_i |Δλ_i| and sets
  /// `nonfinite` when an update or Δu became non-finite.
  double sweep(double* lambda, double* du, bool& nonfinite) const;

  /// Rows with A_ii ≤ 0 (moved to a bound by singular_row_update, never divided by).
  [[nodiscard]] const std::vector<int>& singular_rows() const;

 private:
  std::unique_ptr<MatrixFreeRows> rows_;
};

}  // namespace dc::solvers
