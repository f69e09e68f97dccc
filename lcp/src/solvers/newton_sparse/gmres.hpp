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

/// Σ_i a_i b_i in index order.
double dot_in_order(const Eigen::VectorXd& a, const Eigen::VectorXd& b);

/// Σ_i a_i b_i as eight interleaved partial sums (lane j over i ≡ j mod 8) added pairwise in a
/// fixed tree, then the tail in index order: the same bits in every build, several times faster
/// than dot_in_order's single chain of adds on long vectors, rounded differently.
double dot_in_lanes(const Eigen::VectorXd& a, const Eigen::VectorXd& b);

/// A dot product Σ_i a_i b_i in an order fixed by the source alone (the same bits in every build).
using Dot = double (*)(const Eigen::VectorXd& a, const Eigen::VectorXd& b);

/// Solves K x = b from x = 0 with preconditioner x ≈ P⁻¹ r until ‖b − K x‖ ≤ tolerance·‖b‖ or
/// max_iterations; restarts every `restart` iterations and stops early when a restart cycle
/// does not halve the true residual (the conditioning floor). x is the last iterate. `dot` takes
/// every inner product (Gram–Schmidt and the norms).
KrylovOutcome gmres(const LinearMap& K, const LinearMap& P_inverse, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                    int restart, int max_iterations, double tolerance, Dot dot = dot_in_order);

/// gmres from the start x (the answer of an earlier run on the same K and b, e.g. one with a
/// weaker preconditioner that ended at its cap): r0 = b − K x, and the same stopping rule
/// ‖b − K x‖ ≤ tolerance·‖b‖ (relative to b, not r0), so a start within c·tolerance needs only
/// the iterations that remove a factor c. A start not finite, of another size or with
/// ‖r0‖ ≥ ‖b‖ is dropped (gmres from x = 0). A start that already meets the tolerance returns
/// with 0 iterations.
KrylovOutcome gmres_from(const LinearMap& K, const LinearMap& P_inverse, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                         int restart, int max_iterations, double tolerance, Dot dot = dot_in_order);

}  // namespace dc::solvers
