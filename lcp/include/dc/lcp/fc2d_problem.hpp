#pragma once
// The 2D frictional-contact problem of Siconos numerics (FrictionContactProblem, dimension 2)
// and FCLIB (local, spacedim 2), and its relation to the engine's box-friction LCP. With nc
// contacts, reactions r = (r_n,0, r_t,0, r_n,1, …) [N·s for the engine's problems] and local
// velocity u = W r + q (2nc entries [m/s]), each contact obeys Coulomb's law
//     0 ≤ r_n ⊥ u_n ≥ 0,  |r_t| ≤ μ r_n,  |r_t| < μ r_n ⇒ u_t = 0,  r_t = ±μ r_n ⇒ ∓u_t ≥ 0.
// In 2D this is exactly the box-friction LCP (lcp_problem.hpp): A = W, b = q, normal rows in
// [0, ∞), tangent rows in ±μ r_n; the natural-map residual max_i |λ_i − mid(lo_i, λ_i − w_i,
// hi_i)| is zero exactly at a Coulomb solution. Siconos measures the same solutions through De
// Saxcé's form (u_n + μ|u_t| against the dual cone, normalised by max(‖r‖, ‖u‖, ‖q‖)): a
// different number, zero at the same points.
#include <Eigen/Core>
#include <vector>

#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// A 2D frictional-contact problem: u = W r + q, Coulomb's law per contact (see above).
struct Fc2dProblem {
  SparseRowMatrix W;   ///< 2nc × 2nc, rows and columns per contact (normal, tangent) [m/(N·s)]
  Eigen::VectorXd q;   ///< 2nc, free local velocity [m/s]
  Eigen::VectorXd mu;  ///< nc, friction coefficient of each contact (≥ 0)

  [[nodiscard]] int contacts() const { return static_cast<int>(mu.size()); }
  /// Throws InvalidArgument unless W is 2nc × 2nc, q has 2nc entries, nc ≥ 1, every entry is
  /// finite and every μ ≥ 0.
  void validate() const;
};

/// The box-friction LCP of `p` (A = W, b = q; row 2c normal with [0, ∞), row 2c+1 tangent
/// coupled to row 2c with μ_c). validate()s p first.
LcpProblem fc2d_to_lcp(const Fc2dProblem& p);

/// A 2D frictional-contact problem made from an engine LCP, with the map between the rows.
struct Fc2dFromLcp {
  Fc2dProblem problem;
  /// LCP row of each row of `problem` (2nc entries); −1 for the tangent row added to a
  /// frictionless contact (μ = 0 and no tangent row in the LCP: W gets a decoupled tangent
  /// row with W_tt = W_nn and q_t = 0, which cannot change r since |r_t| ≤ 0).
  std::vector<int> lcp_row;
};

/// Splits an LCP whose rows are contacts (normal rows with bounds [0, ∞), each with at most
/// one tangent row coupled to it) into its 2D frictional-contact form, contacts in the order
/// of their normal rows. Forms A from J when it is absent. Throws InvalidArgument for rows
/// that are neither (other fixed bounds, two tangent rows on one normal row).
Fc2dFromLcp fc2d_from_lcp(const LcpProblem& p);

/// λ of the LCP → r of the frictional problem (0 for added tangent rows).
Eigen::VectorXd fc2d_reactions(const Fc2dFromLcp& map, const Eigen::VectorXd& lambda);

/// Natural-map residual of r for `p` (= natural_residual of fc2d_to_lcp(p)) [units of r].
double fc2d_natural_residual(const Fc2dProblem& p, const Eigen::VectorXd& r);

}  // namespace dc
