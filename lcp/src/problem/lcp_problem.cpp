#include "dc/lcp/lcp_problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "dc/core/error.hpp"

namespace dc {

LcpProblem LcpProblem::standard(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  return standard(SparseRowMatrix(A.sparseView(0.0, 0.0)), b);  // explicit zeros out, no pruning
}

LcpProblem LcpProblem::standard(const SparseRowMatrix& A, const Eigen::VectorXd& b) {
  if (A.rows() != A.cols() || A.rows() != b.size())
    throw InvalidArgument("LcpProblem::standard: A must be n×n and b of size n (A is " +
                          std::to_string(A.rows()) + "×" + std::to_string(A.cols()) +
                          ", b has " + std::to_string(b.size()) + ")");
  LcpProblem p;
  p.A = A;
  p.A.makeCompressed();
  p.b = b;
  const auto n = b.size();
  p.lo = Eigen::VectorXd::Zero(n);
  p.hi = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  p.normal_row.assign(static_cast<size_t>(n), -1);
  p.mu = Eigen::VectorXd::Zero(n);
  return p;
}

void StructureStamp::set(const LcpProblem& p) {
  rows_ = p.rows();
  contacts_ = p.constraints.size();
}

bool StructureStamp::holds(const LcpProblem& p) const {
  return rows_ >= 0 && rows_ == p.rows() && contacts_ == p.constraints.size() && &p.structure == this;
}

void LcpProblem::validate() const {
  const int n = rows();
  auto fail = [](const std::string& m) { throw InvalidArgument("LCP problem: " + m); };
  const bool matrix_free = A.rows() == 0 && A.cols() == 0 && n > 0;  // A formed on demand
  if (matrix_free && !has_jacobian()) fail("neither A nor J is given");
  if (!matrix_free && (A.rows() != n || A.cols() != n))
    fail("A is " + std::to_string(A.rows()) + "×" + std::to_string(A.cols()) + " but b has " +
         std::to_string(n) + " entries");
  if (lo.size() != n || hi.size() != n || mu.size() != n || static_cast<int>(normal_row.size()) != n)
    fail("bounds, mu and normal_row must have one entry per row");
  for (int k = 0; k < A.outerSize(); ++k)
    for (SparseRowMatrix::InnerIterator it(A, k); it; ++it)
      if (!std::isfinite(it.value()))
        fail("A(" + std::to_string(it.row()) + "," + std::to_string(it.col()) + ") is not finite");
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(b[i])) fail("b(" + std::to_string(i) + ") is not finite");
    const int nr = normal_row[static_cast<size_t>(i)];
    if (nr >= 0) {
      if (nr >= n || normal_row[static_cast<size_t>(nr)] >= 0)
        fail("friction row " + std::to_string(i) + " is coupled to row " + std::to_string(nr) +
             ", which is not a normal row");
      if (!(mu[i] >= 0) || !std::isfinite(mu[i]))
        fail("friction coefficient of row " + std::to_string(i) + " must be finite and ≥ 0");
    } else {
      if (std::isnan(lo[i]) || std::isnan(hi[i]) || lo[i] > hi[i] || lo[i] == INFINITY ||
          hi[i] == -INFINITY)
        fail("row " + std::to_string(i) + " has invalid bounds [" + std::to_string(lo[i]) + ", " +
             std::to_string(hi[i]) + "]");
    }
  }
  if (J.rows() > 0) {
    if (J.rows() != n) fail("J has " + std::to_string(J.rows()) + " rows, expected " + std::to_string(n));
    if (inv_mass.size() != J.cols()) fail("inv_mass must have one entry per column of J");
    if (!(dt > 0)) fail("dt must be > 0 when J is given");
  }
  validate_constraints();
}

void LcpProblem::validate_constraints() const {
  if (constraints.empty()) return;
  const int n = rows();
  auto fail = [](const std::string& m) { throw InvalidArgument("LCP problem: " + m); };
  if (constraints.rows() != n)
    fail("the contacts own " + std::to_string(constraints.rows()) + " rows, the problem has " + std::to_string(n));
  const int bodies = static_cast<int>(J.cols() / 3);
  std::vector<char> owned(static_cast<size_t>(n), 0);
  for (int c = 0; c < constraints.size(); ++c) {
    const ContactConstraint& k = constraints[c];
    // The name is formatted only on failure: formatting it for every contact would be a
    // noticeable part of a short solve.
    const auto name = [c] { return "contact " + std::to_string(c); };
    if (J.rows() > 0 && (k.body_b >= bodies || k.body_a >= bodies))
      fail(name() + " acts on a body beyond the " + std::to_string(bodies) + " bodies of J");
    for (const int r : {k.normal_row, k.tangent_row}) {
      if (r < 0) continue;
      if (r >= n || owned[static_cast<size_t>(r)]++)
        fail(name() + ": row " + std::to_string(r) + " is out of range or owned by another contact");
    }
    if (k.normal_row < 0 || normal_row[static_cast<size_t>(k.normal_row)] >= 0)
      fail(name() + ": its normal row is missing or is a friction row");
    if (k.has_friction() != (k.mu > 0)) fail(name() + ": a tangent row needs mu > 0 and mu > 0 a tangent row");
    if (k.has_friction() && (normal_row[static_cast<size_t>(k.tangent_row)] != k.normal_row || mu[k.tangent_row] != k.mu))
      fail(name() + ": tangent row " + std::to_string(k.tangent_row) + " is not coupled to its normal row with its mu");
  }
}

void LcpProblem::ensure_assembled_matrix() {
  if (has_assembled_matrix() || !has_jacobian()) return;
  // A = J M⁻¹ Jᵀ Δt, kept row-major and sparse (rows couple only through shared bodies).
  const SparseRowMatrix JM = J * (inv_mass * dt).asDiagonal();
  A = (JM * SparseRowMatrix(J.transpose())).pruned(0.0);
  A.makeCompressed();
}

namespace {

/// Δu = Δt M⁻¹ Jᵀ λ per dof [m/s, rad/s], as the matrix-free PGS keeps it.
Eigen::VectorXd velocity_change(const LcpProblem& p, const Eigen::VectorXd& lambda) {
  Eigen::VectorXd du = p.J.transpose() * lambda;
  for (int c = 0; c < du.size(); ++c) du[c] = p.inv_mass[c] * du[c] * p.dt;
  return du;
}

}  // namespace

Eigen::VectorXd lcp_velocity(const LcpProblem& p, const Eigen::VectorXd& lambda) {
  if (p.has_jacobian()) return p.J * velocity_change(p, lambda) + p.b;  // w = J Δu + b
  return p.A * lambda + p.b;
}

Eigen::VectorXd lcp_apply(const LcpProblem& p, const Eigen::VectorXd& lambda) {
  if (p.has_jacobian()) return p.J * velocity_change(p, lambda);
  return p.A * lambda;
}

double natural_map_row(const LcpProblem& p, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w, int i) {
  const double l = p.lower(i, lambda), h = p.upper(i, lambda);
  return lambda[i] - std::clamp(lambda[i] - w[i], l, std::max(l, h));
}

double natural_residual(const LcpProblem& p, const Eigen::VectorXd& lambda) {
  const Eigen::VectorXd w = lcp_velocity(p, lambda);
  double r = 0.0;
  for (int i = 0; i < p.rows(); ++i) {
    const double e = std::abs(natural_map_row(p, lambda, w, i));
    if (std::isnan(e)) return std::numeric_limits<double>::infinity();
    r = std::max(r, e);
  }
  return r;
}

double natural_residual_l2(const LcpProblem& p, const Eigen::VectorXd& lambda) {
  const Eigen::VectorXd w = lcp_velocity(p, lambda);
  double sum = 0.0;
  for (int i = 0; i < p.rows(); ++i) {
    const double e = natural_map_row(p, lambda, w, i);
    sum += e * e;
  }
  return std::isfinite(sum) ? std::sqrt(sum) : std::numeric_limits<double>::infinity();
}

void project_feasible(const LcpProblem& p, Eigen::Ref<Eigen::VectorXd> lambda) {
  if (lambda.size() != p.rows())
    throw InvalidArgument("project_feasible: λ has " + std::to_string(lambda.size()) +
                          " entries, the problem has " + std::to_string(p.rows()) + " rows");
  // Normal (fixed-bound) rows first, then friction rows whose bounds depend on them.
  for (int i = 0; i < p.rows(); ++i) {
    if (!std::isfinite(lambda[i])) lambda[i] = 0.0;
    if (!p.is_friction_row(i)) lambda[i] = std::clamp(lambda[i], p.lo[i], p.hi[i]);
  }
  for (int i = 0; i < p.rows(); ++i)
    if (p.is_friction_row(i)) lambda[i] = std::clamp(lambda[i], p.lower(i, lambda), p.upper(i, lambda));
}

}  // namespace dc
