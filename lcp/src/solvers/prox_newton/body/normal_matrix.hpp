#pragma once
// H = W⁻¹ + Jᵀ D J (D diagonal, one weight per row of J) in a pattern fixed per J: the matrix
// BodyNewton factorises on every Newton iteration whose D changed.
//
// bind() computes, once per J, H's pattern (row-major, sorted, the full symmetric matrix: every
// (a, b) with a, b columns of one row of J, plus the diagonal) and for each row r of J the slot
// in H's values of every product pair (k, l) of r's stored entries. assemble() then zeroes the
// values and adds, row by row in increasing r, D_r J_ra J_rb into entry (a, b), and W⁻¹ on the
// diagonal last: per entry the sums of Eigen's `Jt * (D.asDiagonal() * J) + diag(W⁻¹)` in the
// same order, so the same bits (Eigen's product takes the terms of entry (a, b) in increasing r;
// its first term is assigned, here added to +0, and a row with D_r = 0 would add ±0: both change at
// most the sign of an exact zero, which the sparse sum's "+ 0" for entries diag(W⁻¹) lacks makes
// +0 in Eigen's result as it is here). The pattern is structural (stored zeros of J and rows with
// D_r = 0 keep their entries), so it is the same whatever D is and FreeBlockFactor keeps its
// symbolic analysis across iterations.
#include <Eigen/Core>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"

namespace dc::solvers::prox {

class NormalMatrix {
 public:
  /// H's pattern and the slots for J's pattern (no duplicate entries in a row); Jt = Jᵀ
  /// (row-major: its row a lists the rows of J that touch column a).
  void bind(const SparseRowMatrix& J, const SparseRowMatrix& Jt);
  /// H's values for J (the pattern of the last bind()), W⁻¹'s diagonal winv (J.cols() entries)
  /// and the row weights d (J.rows() entries; rows with d_r = 0 add nothing).
  void assemble(const SparseRowMatrix& J, const Eigen::VectorXd& winv, const Eigen::VectorXd& d);
  /// H after the last assemble() (its pattern after bind()).
  [[nodiscard]] const SparseRowMatrix& matrix() const { return H_; }

 private:
  SparseRowMatrix H_;
  std::vector<int> pair_start_;  // row r's slots: from slot_[pair_start_[r]], (k, l) in row-major order
  std::vector<int> slot_;        // index into H_'s values of entry (col k, col l) of row r
  std::vector<int> diag_slot_;   // index of H_(a, a)
  std::vector<int> mark_, pos_, cols_, row_start_;  // bind()'s work: kept to reuse their storage
};

}  // namespace dc::solvers::prox
