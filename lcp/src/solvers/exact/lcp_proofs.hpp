#pragma once
// What a standard LCP  w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0  can be *proved* not to have: the
// evidence behind the `infeasible` status (docs/lcp.md "What `infeasible` proves", with proofs).
// 1. Farkas certificate: y ≥ 0 with Mᵀy ≤ 0 and qᵀy < 0 (then no z ≥ 0 has Mz + q ≥ 0), found
//    as the LCP of the KKT conditions of "y ≥ 0, Mᵀy ≤ 0, qᵀy ≤ −1" (skew-symmetric, so Lemke
//    decides it) and then checked on the original data — the check, not the search, is the proof.
// 2. Exhaustive enumeration (small n): if every principal submatrix M_αα is nonsingular, every
//    solution is the basic solution of one of the 2ⁿ index sets, so all 2ⁿ infeasible proves
//    there is none; a singular M_αα makes it prove nothing, and the enumeration says so.
// Floating-point margins: a certificate needs each (Mᵀy)_j ≤ 1e-12·Σ_i |M_ij| y_i and qᵀy clearly
// negative; an enumeration needs every M_αα with reciprocal condition ≥ 1e-10 and every basic
// solution to miss feasibility by a clear margin.
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
