#pragma once
// The factorised preconditioner of newton-sparse: the full-size matrix
//
//     P = [ A_FF + ρI   0 ]      (rows and columns permuted back to the LCP's order)
//         [ 0          I_C ]
//
// for a free-row mask F (the clamped rows C get an identity row and column). Its pattern is
// that of A ∪ diag whatever F is, so one symbolic analysis serves every Newton iteration, and
// every solve of a problem with the same pattern of A (a settled pile keeps its contacts).
//
// Symmetric A (every contact problem): CHOLMOD's simplicial LDLᵀ of the lower triangle (or,
// with `supernodal`, whichever of simplicial and supernodal CHOLMOD picks from the fill); when it meets a non-positive pivot, Eigen's
// SimplicialLDLT of the same matrix. Non-symmetric A (general LCPs from files): Eigen's
// SparseLU of the whole matrix. A_FF + ρI is positive definite for a PSD A and ρ > 0.
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/newton_sparse.hpp"

namespace dc::solvers {

class FreeBlockFactor {
 public:
  /// use_cholmod: false = SimplicialLDLT only; reuse_analysis: keep the analysis across bind()s
  /// while the pattern of A is unchanged; supernodal: let CHOLMOD choose supernodal LLᵀ (BLAS)
  /// where the fill favours it, else CHOLMOD's simplicial LDLᵀ always.
  FreeBlockFactor(bool use_cholmod, bool reuse_analysis, bool supernodal = false);
  ~FreeBlockFactor();
  FreeBlockFactor(const FreeBlockFactor&) = delete;
  FreeBlockFactor& operator=(const FreeBlockFactor&) = delete;

  /// Prepares for a problem with matrix A (compressed): keeps the pattern and the analysis when
  /// A's pattern and symmetry are those of the previous bind(), else rebuilds them lazily. With
  /// the pattern kept, the last numeric factor stays available to solve() (a stale factor: of
  /// the earlier matrix's values, usable as a preconditioner).
  void bind(const SparseRowMatrix& A, bool symmetric);
  /// Numeric factorisation of P for the mask (free[i] ≠ 0: row i free) and ρ [m/(N·s)].
  /// False when every available factorisation failed.
  bool factorize(const std::vector<char>& free, double rho, NewtonSparseStats& stats);
  /// x = P⁻¹ r of the last successful factorize() (of this pattern).
  void solve(const Eigen::VectorXd& r, Eigen::VectorXd& x) const;
  /// True when solve() has a factor: factorize() succeeded since the pattern was last rebuilt.
  [[nodiscard]] bool factored() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dc::solvers
