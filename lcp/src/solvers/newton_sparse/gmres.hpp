#pragma once
// Restarted GMRES with right preconditioning, for the non-symmetric Newton system of
// newton-sparse: K x = b with K = P + E, where P (the factorised free block) is exact except
// for the friction coupling E. K P⁻¹ = I + E P⁻¹ differs from I by a matrix of rank ≤ the
// number of sliding contacts, so GMRES needs few iterations. Sums run in index order (no
// packet-order reductions: the same iterates in every build).
#include <Eigen/Core>
#include <functional>

namespace dc::solvers {

struct KrylovOutcome {
  int iterations = 0;
  double relative_residual = 0;  ///< ‖b − K x‖ / ‖b‖ at return (GMRES's estimate)
  bool converged = false;
};

using LinearMap = std::function<void(const Eigen::VectorXd& in, Eigen::VectorXd& out)>;

/// Solves K x = b from x = 0 with preconditioner x ≈ P⁻¹ r until ‖b − K x‖ ≤ tolerance·‖b‖ or
/// max_iterations; restarts every `restart` iterations and stops early when a restart cycle
/// does not halve the true residual (the conditioning floor). x is the last iterate.
KrylovOutcome gmres(const LinearMap& K, const LinearMap& P_inverse, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                    int restart, int max_iterations, double tolerance);

/// Σ_i a_i b_i in an order fixed by the source alone (eight interleaved partial sums added
/// pairwise, then the tail in index order): the same bits in every build, not Eigen's dot.
double dot_in_order(const Eigen::VectorXd& a, const Eigen::VectorXd& b);

}  // namespace dc::solvers
