#pragma once
// y = A x for a compressed row-major sparse A, with the bits of Eigen's product
// (`y.noalias() = A * x`): every row's sum runs over its stored entries in order from +0
// (Eigen then adds it to a zeroed y, which changes no bit: a sum from +0 is never −0).
// Eigen's loop keeps one chain of dependent adds per row, which waits an add's latency per
// entry; here four rows run side by side (four independent chains, each in its own row's
// order), so the same sums wait about a quarter as long. GMRES in newton-sparse applies A once
// per iteration (apply_system), on contact problems with about a dozen entries per row.
#include <Eigen/Core>

#include "dc/lcp/kept_sparse_matrix.hpp"

namespace dc::solvers {

/// y = A x (A compressed; y resized to A's rows), bit-equal to `y.noalias() = A * x`.
void row_product(const SparseRowMatrix& A, const Eigen::VectorXd& x, Eigen::VectorXd& y);

}  // namespace dc::solvers
