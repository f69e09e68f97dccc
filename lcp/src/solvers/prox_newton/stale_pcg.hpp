#pragma once
// Preconditioned conjugate gradients for prox-newton's body-space Newton system H d = −F
// (body_newton.hpp) with the Cholesky factor of an earlier H as preconditioner (Drake's SAP and
// MuJoCo keep theirs the same way): H − H_old = Jᵀ(D − D_old)J has the rank of the rows whose
// mode changed, so CG on P⁻¹H converges in about that many iterations plus one. Sums run in
// index order (the same iterates in every build).
#include <Eigen/Core>

#include "solvers/newton_sparse/gmres.hpp"

namespace dc::solvers::prox {

struct PcgOutcome {
  int iterations = 0;
  bool converged = false;  ///< ‖b − H x‖_{P⁻¹} ≤ tolerance · ‖b‖_{P⁻¹} within max_iterations
};

/// Solves H x = b from x = P⁻¹ b (H SPD as a map, P⁻¹ an SPD preconditioner) until the
/// preconditioned residual norm falls to tolerance times its value at x = 0, or max_iterations.
/// x is the last iterate (a descent direction for the quadratic with Hessian H and gradient −b
/// at every iteration).
PcgOutcome pcg(const LinearMap& H, const LinearMap& P_inverse, const Eigen::VectorXd& b, Eigen::VectorXd& x,
               int max_iterations, double tolerance);

}  // namespace dc::solvers::prox
