#pragma once
// What a standard LCP  w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0  can be *proved* not to have:
// the evidence behind the `infeasible` status (docs/lcp.md "What infeasible proves").
//
// 1. Farkas certificate. If some y ≥ 0 has Mᵀy ≤ 0 and qᵀy < 0, then for every z ≥ 0
//    yᵀ(Mz + q) = (Mᵀy)ᵀz + qᵀy < 0, so some w_i < 0: not even the linear part
//    {z ≥ 0, Mz + q ≥ 0} has a point, let alone a complementary one. By Farkas' lemma such
//    a y exists exactly when that set is empty. It is found by solving the LP
//    "y ≥ 0, Mᵀy ≤ 0, qᵀy ≤ −1" as the LCP of its KKT conditions, whose matrix is
//    skew-symmetric (hence copositive-plus, so Lemke's method decides it), and it is checked
//    on the original data afterwards — the check, not the search, is the proof. For
//    copositive-plus M (e.g. M + Mᵀ positive semidefinite) an LCP without solution always
//    has an empty feasible set (Lemke's theorem), so this certificate covers them all.
// 2. Exhaustive enumeration (small n). Every solution with support α = {i : z_i > 0}
//    satisfies M_αα z_α = −q_α. If every principal submatrix M_αα is nonsingular, each
//    solution is therefore the basic solution of one of the 2ⁿ index sets α, so finding all
//    2ⁿ basic solutions infeasible proves there is none. With a singular M_αα it proves
//    nothing (solutions can then lie off the bases) and the enumeration says so.
// Both checks are in floating point: a certificate is accepted when each (Mᵀy)_j is ≤ 0 up
// to 1e-12 of Σ_i |M_ij| y_i (the round-off of the sum) and qᵀy is clearly negative; an
// enumeration proves infeasibility only if every M_αα has reciprocal condition ≥ 1e-10 and
// every basic solution misses feasibility by a clear margin.
#include <Eigen/Core>
#include <functional>
#include <string>

namespace dc::solvers {

/// Largest n for which the Farkas certificate is searched (its LP tableau has (2n+1)·(4n+4) entries).
inline constexpr int kFarkasMaxN = 500;
/// Largest n for which the 2ⁿ complementary bases are enumerated.
inline constexpr int kEnumerateMaxN = 16;

struct FarkasCertificate {
  bool found = false;
  Eigen::VectorXd y;   ///< y ≥ 0 with Mᵀy ≤ 0, qᵀy < 0 (in the original units) when found
  std::string detail;  ///< what was checked, or why there is none
};

/// Searches and verifies a Farkas certificate for {z ≥ 0, Mz + q ≥ 0} = ∅ (n ≤ kFarkasMaxN).
FarkasCertificate find_farkas_certificate(const Eigen::MatrixXd& M, const Eigen::VectorXd& q);

/// Verifies y as a certificate for (M, q) as described above; `detail` gets the figures.
bool check_farkas_certificate(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Eigen::VectorXd& y,
                              std::string& detail);

struct BasisEnumeration {
  bool solved = false;         ///< `accept` took a basic solution
  bool proves_none = false;    ///< every basis nonsingular and clearly infeasible
  Eigen::VectorXd z;           ///< the accepted solution
  long long bases = 0;         ///< bases examined
  long long singular = 0;      ///< bases with an (almost) singular M_αα
  long long borderline = 0;    ///< basic solutions infeasible by less than the margin
  std::string detail;
};

/// Enumerates the complementary bases of w = Mz + q (n ≤ kEnumerateMaxN; M, q scaled to
/// entries O(1)). For each nearly feasible basic solution z (clamped ≥ 0) calls
/// accept(z); stops at the first one it takes.
BasisEnumeration enumerate_complementary_bases(const Eigen::MatrixXd& M, const Eigen::VectorXd& q,
                                               const std::function<bool(const Eigen::VectorXd&)>& accept);

}  // namespace dc::solvers
