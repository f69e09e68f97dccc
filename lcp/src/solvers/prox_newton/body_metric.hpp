#pragma once
// The body-space quantities both body-space Newton solvers (BodyNewton's Tresca passes and
// ConeNewton's exact-cone passes) take from a problem: the velocity metric W = Δt·M⁻¹ and its
// inverse, Jᵀ, and the largest diagonal entry of A = J W Jᵀ (the scale of their shifts).
#include <Eigen/Core>

#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// Fills Jt = Jᵀ, w = Δt·M⁻¹ (3 entries per body), winv = W⁻¹ (1e300 for a body of infinite
/// mass, M⁻¹ = 0: it does not move and H stays finite), Winv_diag = diag(winv) as a sparse
/// matrix, and max_diag = max_i Σ_j J_ij² w_j. The outputs' storage is reused.
void bind_body_metric(const LcpProblem& p, SparseRowMatrix& Jt, Eigen::VectorXd& w, Eigen::VectorXd& winv,
                      SparseRowMatrix& Winv_diag, double& max_diag);

}  // namespace dc
