#pragma once
// Lemke's complementary pivoting on a dense tableau, the core shared by the `lemke` solver
// (its first attempt with covering vector d = 1 and the retries with other d) and by the
// Farkas-certificate search of lcp_proofs.hpp (an LP posed as a skew-symmetric LCP).
//
// Standard LCP w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0 with an artificial variable z₀ and
// covering vector d > 0: tableau [ I | −M | −d | q ], w basic at the start. If q ≥ 0, z = 0
// solves it with no pivot. Otherwise z₀ enters at the row minimising q_i/d_i; then the
// complement of each leaving variable enters. Ratio test with lexicographic tie-breaking
// (rows of B⁻¹ — the tableau's w block — divided by the pivot-column entry), which prevents
// cycling on degenerate problems; z₀ leaves as soon as it ties. Terminations:
//   * z₀ leaves the basis     → a complementary solution (Outcome::Solved)
//   * no positive pivot entry → secondary ray (Outcome::Ray). This proves infeasibility only
//                                when M is copositive-plus; the caller decides what it proves.
//   * pivot cap reached / tableau non-finite → Outcome::Stopped
// The caller scales M and q (entries O(1)); nothing here depends on units.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace dc::solvers {

struct LemkePivoting {
  enum class Outcome { Solved, Ray, Stopped };
  Outcome outcome = Outcome::Stopped;
  Eigen::VectorXd z;        ///< the basic z values at termination (zero elsewhere), clamped ≥ 0
  std::vector<int> active;  ///< indices of the basic z's (the candidate active set) when Solved
  int pivots = 0;
  std::string why;          ///< what happened, for messages
};

/// Runs Lemke's method on w = M z + q with covering vector d (all d_i > 0) and at most `cap`
/// pivots. M must be square with q and d of its size.
LemkePivoting lemke_pivoting(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Eigen::VectorXd& d, int cap);

}  // namespace dc::solvers
