#pragma once
// The contact impulse of integration (integrate_bodies) on the step's threads.
#include <Eigen/Core>

#include "dc/lcp/lcp_problem.hpp"

namespace dc {

/// impulse ← Δt · Jᵀλ [N·s] as Eigen evaluates `J.transpose() * lambda * dt` (each dof's sum
/// accumulated from 0 in row order, then multiplied by Δt: the same numbers). On `threads`
/// threads by blocks of whole bodies' columns (J has 3 columns per body): each block sums, in row
/// order, the rows that act on it (found first by ranges of rows), so every thread count gives
/// the same bits.
void contact_impulse(const SparseRowMatrix& J, const Eigen::VectorXd& lambda, double dt, Eigen::VectorXd& impulse,
                     int threads);

}  // namespace dc
