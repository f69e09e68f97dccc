#pragma once
// The contact LCP of one step (docs/design.md §2), in the form every solver consumes:
//     w = A λ + b,   lo_i ≤ λ_i ≤ hi_i,  and for each row exactly one of
//       λ_i = lo_i and w_i ≥ 0,   λ_i = hi_i and w_i ≤ 0,   lo_i < λ_i < hi_i and w_i = 0.
// Friction rows: hi_i = μ_i λ_{n(i)}, lo_i = −hi_i, n(i) = normal_row[i]; rows with
// normal_row[i] < 0 have fixed bounds (lo = 0, hi = +∞ for normal rows and standard LCPs).
// An assembled problem carries J, M⁻¹, Δt and its contact constraints (the matrix-free solvers
// use those); A = J M⁻¹ Jᵀ Δt is NOT formed by assembly: whoever needs A calls
// ensure_assembled_matrix() first (World::step and the bench do when needs_assembled_matrix());
// an assembled solver handed a problem without A forms it for that one solve. A problem read
// from a file has only A and b (no J, no constraints).
// b, lo, hi, μ and M⁻¹ are KeptVectors and J a KeptSparseRowMatrix: storage that a World's step
// refills without an allocation while the row count stays within what it held before.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "dc/lcp/contact_constraints.hpp"
#include "dc/lcp/kept_sparse_matrix.hpp"
#include "dc/lcp/kept_vector.hpp"

namespace dc {

struct LcpProblem;

/// Whether a problem's structure was written valid by construction by the code that built it
/// in place (the engine's assembly, assemble_lcp): each contact's rows numbered as
/// ContactConstraints::add numbers them, after add()'s checks, on bodies of J, normal rows with
/// bounds [0, +∞), tangent rows coupled to their contact's normal row with its finite μ ≥ 0.
/// What it does not vouch for are the values that change every step and can fail (b, A and
/// λ⁰ finite): a solver that reads the stamp ("pgs-colored") still checks those, and runs the
/// full checks, with their messages, when they fail. The stamp cannot outlive the problem it
/// was set on: a copy or an assignment of a problem is unstamped (a copy may be edited freely),
/// and it holds only while the problem has the rows and contacts it had when stamped. Whoever
/// edits a stamped problem's structure in place (normal_row, lo, hi, mu, constraints, J's
/// shape) must clear() it; the engine's problems are exposed only as const.
class StructureStamp {
 public:
  StructureStamp() = default;
  StructureStamp(const StructureStamp&) noexcept {}  // a copy starts unstamped
  StructureStamp& operator=(const StructureStamp&) noexcept {
    clear();
    return *this;
  }
  ~StructureStamp() = default;
  /// Stamps p (whose member this is): its structure was written valid by construction.
  void set(const LcpProblem& p);
  void clear() { rows_ = contacts_ = -1; }
  /// True when set() stamped p and p still has the rows and contacts it had then.
  [[nodiscard]] bool holds(const LcpProblem& p) const;

 private:
  int rows_ = -1, contacts_ = -1;
};

struct LcpProblem {
  /// n × n, row-major [m/(N·s)] for contact problems; 0 × 0 until ensure_assembled_matrix()
  /// for a problem assembled from a world.
  SparseRowMatrix A;
  KeptVector b;                ///< n [m/s]
  KeptVector lo;               ///< n, fixed lower bounds (ignored for friction rows)
  KeptVector hi;               ///< n, fixed upper bounds (+∞ allowed; ignored for friction rows)
  std::vector<int> normal_row; ///< n; −1, or the normal row a friction row is coupled to
  KeptVector mu;               ///< n; friction coefficient of friction rows (0 elsewhere)

  // Optional matrix-free representation (empty when the problem came from a file).
  KeptSparseRowMatrix J;       ///< n × 3·bodies, columns (v_x, v_y, ω) per body
  KeptVector inv_mass;         ///< 3·bodies, diagonal of M⁻¹
  double dt = 0.0;             ///< Δt [s] with A = J M⁻¹ Jᵀ Δt
  /// Rows, bodies and μ of each contact (empty when the problem came from a file). When not
  /// empty its rows() equals rows() and it agrees with normal_row and mu (validate()).
  ContactConstraints constraints;
  /// Set by the builder that wrote the structure valid by construction (assemble_lcp); empty
  /// for a problem built by hand, read from a file or copied (StructureStamp).
  StructureStamp structure;

  [[nodiscard]] int rows() const { return static_cast<int>(b.size()); }
  [[nodiscard]] bool has_jacobian() const { return J.rows() == rows() && J.rows() > 0 && dt > 0; }
  /// True when A is present (always for problems from files; after ensure_assembled_matrix()
  /// for assembled ones).
  [[nodiscard]] bool has_assembled_matrix() const { return A.rows() == rows() && A.cols() == rows(); }
  /// Forms A = J M⁻¹ Jᵀ Δt (sparse, row-major, exact zeros pruned) when it is absent and J is
  /// present; otherwise does nothing. Explicit and non-const on purpose: no hidden cache.
  void ensure_assembled_matrix();
  [[nodiscard]] bool is_friction_row(int i) const { return normal_row[static_cast<size_t>(i)] >= 0; }

  /// Effective bounds of row i at the current iterate λ (any vector with operator[]).
  template <class Vector>
  [[nodiscard]] double lower(int i, const Vector& lambda) const {
    const int n = normal_row[static_cast<size_t>(i)];
    return n < 0 ? lo[i] : -mu[i] * std::max(0.0, lambda[n]);
  }
  template <class Vector>
  [[nodiscard]] double upper(int i, const Vector& lambda) const {
    const int n = normal_row[static_cast<size_t>(i)];
    return n < 0 ? hi[i] : mu[i] * std::max(0.0, lambda[n]);
  }

  /// Standard LCP (lo = 0, hi = +∞, no friction) from dense or sparse A and b.
  static LcpProblem standard(const Eigen::MatrixXd& A, const Eigen::VectorXd& b);
  static LcpProblem standard(const SparseRowMatrix& A, const Eigen::VectorXd& b);

  /// Throws InvalidArgument if sizes disagree, an entry is non-finite, a bound pair is
  /// inverted, a friction row points at a non-normal row, neither A nor J is present, or the
  /// constraints disagree with the rows (a row owned by no or two contacts, a tangent row not
  /// coupled to its contact's normal row, a μ that differs from mu, a body outside J).
  void validate() const;

 private:
  void validate_constraints() const;
};

/// Clamps λ into the problem's bounds (λ_n ≥ 0, |λ_t| ≤ μ λ_n, fixed bounds elsewhere) and
/// replaces non-finite entries by 0, so any guess is a valid PGS starting point: normal
/// (fixed-bound) rows first, then the friction rows whose bounds depend on them. Each row's
/// result depends only on its own contact's rows, so the clamp commutes with any permutation
/// of whole contacts (World's builtin warm start in its internal row order relies on it).
void project_feasible(const LcpProblem& problem, Eigen::Ref<Eigen::VectorXd> lambda);

/// Natural-map residual, the step-length-independent accuracy measure of docs/design.md §2:
///   max_i |λ_i − mid(lo_i, λ_i − w_i, hi_i)|   with w = A λ + b and the effective bounds.
/// Zero exactly at a solution; units of λ [N].
double natural_residual(const LcpProblem& p, const Eigen::VectorXd& lambda);

/// Row i of the natural map, λ_i − mid(lo_i, λ_i − w_i, hi_i), with the effective bounds and
/// w = A λ + b given (natural_residual is the largest |value| over the rows).
double natural_map_row(const LcpProblem& p, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w, int i);

/// The same natural map in the 2-norm, ‖λ − mid(lo, λ − w, hi)‖₂ [N]: the whole error rather
/// than its worst row (gate-l2). +∞ when an entry is not finite.
double natural_residual_l2(const LcpProblem& p, const Eigen::VectorXd& lambda);

/// w = A λ + b. A problem with J is evaluated matrix-free, w = J (Δt M⁻¹ Jᵀ λ) + b (O(nnz J),
/// A need not be formed; equal to A λ + b up to round-off), a problem from a file with A.
Eigen::VectorXd lcp_velocity(const LcpProblem& p, const Eigen::VectorXd& lambda);

/// A λ alone (lcp_velocity without b) [m/s]: matrix-free, J (Δt M⁻¹ Jᵀ λ), with the same
/// operations as lcp_velocity when p has J; else A λ. For Krylov solves on A (builtin-coarse's
/// Galerkin CG, the active-set CGLS) outside the engine.
Eigen::VectorXd lcp_apply(const LcpProblem& p, const Eigen::VectorXd& lambda);

}  // namespace dc
