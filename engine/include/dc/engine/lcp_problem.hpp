#pragma once
// The contact LCP of one step (DESIGN §2), in the form every solver consumes:
//
//     w = A λ + b,   lo_i ≤ λ_i ≤ hi_i,  and for each row exactly one of
//       λ_i = lo_i and w_i ≥ 0,   λ_i = hi_i and w_i ≤ 0,   lo_i < λ_i < hi_i and w_i = 0.
//
// Friction rows have bounds that depend on the solution: hi_i = μ_i λ_{n(i)}, lo_i = −hi_i,
// where n(i) = normal_row[i] is the normal row of the same contact. Rows with
// normal_row[i] < 0 have the fixed bounds lo_i, hi_i (lo = 0, hi = +∞ for normal rows and
// for standard LCPs read from files).
//
// A problem assembled from a world also carries J and M⁻¹ (so that A = J M⁻¹ Jᵀ Δt) which
// the matrix-free solvers use instead of A; a problem read from a file has only A and b.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace dc {

using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

struct LcpProblem {
  SparseRowMatrix A;           ///< n × n, row-major [m/(N·s)] for contact problems
  Eigen::VectorXd b;           ///< n [m/s]
  Eigen::VectorXd lo;          ///< n, fixed lower bounds (ignored for friction rows)
  Eigen::VectorXd hi;          ///< n, fixed upper bounds (+∞ allowed; ignored for friction rows)
  std::vector<int> normal_row; ///< n; −1, or the normal row a friction row is coupled to
  Eigen::VectorXd mu;          ///< n; friction coefficient of friction rows (0 elsewhere)

  // Optional matrix-free representation (empty when the problem came from a file).
  SparseRowMatrix J;           ///< n × 3·bodies, columns (v_x, v_y, ω) per body
  Eigen::VectorXd inv_mass;    ///< 3·bodies, diagonal of M⁻¹
  double dt = 0.0;             ///< Δt [s] with A = J M⁻¹ Jᵀ Δt

  [[nodiscard]] int rows() const { return static_cast<int>(b.size()); }
  [[nodiscard]] bool has_jacobian() const { return J.rows() == rows() && J.rows() > 0 && dt > 0; }
  [[nodiscard]] bool is_friction_row(int i) const { return normal_row[static_cast<size_t>(i)] >= 0; }

  /// Effective bounds of row i at the current iterate λ.
  [[nodiscard]] double lower(int i, const Eigen::VectorXd& lambda) const {
    const int n = normal_row[static_cast<size_t>(i)];
    return n < 0 ? lo[i] : -mu[i] * std::max(0.0, lambda[n]);
  }
  [[nodiscard]] double upper(int i, const Eigen::VectorXd& lambda) const {
    const int n = normal_row[static_cast<size_t>(i)];
    return n < 0 ? hi[i] : mu[i] * std::max(0.0, lambda[n]);
  }

  /// Standard LCP (lo = 0, hi = +∞, no friction) from dense or sparse A and b.
  static LcpProblem standard(const Eigen::MatrixXd& A, const Eigen::VectorXd& b);
  static LcpProblem standard(const SparseRowMatrix& A, const Eigen::VectorXd& b);

  /// Throws InvalidArgument if sizes disagree, an entry is non-finite, a bound pair is
  /// inverted, or a friction row points at a non-normal row.
  void validate() const;
};

/// Natural-map residual, the step-length-independent accuracy measure of DESIGN §2:
///   max_i |λ_i − mid(lo_i, λ_i − w_i, hi_i)|   with w = A λ + b and the effective bounds.
/// Zero exactly at a solution; units of λ [N].
double natural_residual(const LcpProblem& p, const Eigen::VectorXd& lambda);

/// w = A λ + b.
Eigen::VectorXd lcp_velocity(const LcpProblem& p, const Eigen::VectorXd& lambda);

}  // namespace dc
