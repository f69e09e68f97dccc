// The LCP solved on a given active set (active_set_solve.hpp). Per contact, by its mode:
//   Separating:     λ_n = λ_t = 0 (fixed);
//   Sticking:       λ_n, λ_t free, equations w_n = 0, w_t = 0;
//   Sliding ±:      λ_n free, λ_t = ±μ λ_n, equation w_n = 0.
// With the free variables x and λ = L x (a sliding friction row follows its normal), the
// equations are the square system S A L x = −S b (S selects the equation rows: the rows of
// the free variables). It is singular where the pile is statically indeterminate (more rows
// than body degrees of freedom: the null space of A); the guess is the solution nearest
// base's free values x_b,
//
//     x = x_b + argmin ‖y‖  s.t.  S A L y = −S (A L x_b + b)       (least squares if inconsistent)
//
// the minimum-norm (least-squares) solution by a complete orthogonal decomposition of the
// dense S A L, then λ⁰ = project(L x). What the active set does not give is the strict
// inequalities (λ_n > 0 of touching contacts, |λ_t| < μ λ_n of sticking ones, w ≥ 0 of
// separating ones): only the projection enforces them.
#include "active_set_solve.hpp"

#include <Eigen/QR>
#include <cmath>
#include <string>
#include <utility>

#include "dc/engine/error.hpp"
#include "starters.hpp"

namespace dc {

ContactMode contact_mode(const ContactConstraints& cons, int c, const Eigen::VectorXd& lambda) {
  const ContactConstraint& k = cons[c];
  const double ln = lambda[k.normal_row];
  if (!(ln > 0)) return ContactMode::Separating;
  if (!k.has_friction()) return ContactMode::Sticking;
  const double lt = lambda[k.tangent_row];
  if (std::abs(lt) < k.mu * ln * (1 - 1e-9)) return ContactMode::Sticking;
  return lt > 0 ? ContactMode::SlidingPlus : ContactMode::SlidingMinus;
}

Eigen::VectorXd min_norm_solve(const Eigen::MatrixXd& M, const Eigen::VectorXd& rhs, double threshold) {
  // The threshold must be set BEFORE compute(): Eigen's COD builds its Z transform for the
  // rank it sees during compute (then the default threshold, ε · size), while solve() uses the
  // rank under the threshold in force at solve time. Setting it afterwards made solve() apply
  // Householder coefficients compute() never wrote (uninitialised heap memory) whenever the
  // two ranks differed: the guess then depended on what the allocator handed out (session 10).
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(M.rows(), M.cols());
  cod.setThreshold(threshold);
  cod.compute(M);
  return cod.solve(rhs);
}

Eigen::VectorXd solve_on_active_set(const World& w, const Eigen::VectorXd& base,
                                    const std::vector<ContactMode>& modes, const char* who) {
  const LcpProblem& p = w.problem();
  require_dense_diagnostic_size(p, who);
  if (modes.size() != w.contacts().size()) throw InvalidArgument(std::string(who) + ": one mode per contact expected");
  // Free variables (one per touching normal row and sticking friction row) and L.
  const ContactConstraints& cons = w.constraints();
  const int rows = p.rows();
  std::vector<int> var_row;                   // variable → its row (and equation row)
  std::vector<std::vector<std::pair<int, double>>> columns;  // (row, coefficient) of L's column, ≤ 2
  for (std::size_t c = 0; c < w.contacts().size(); ++c) {
    const ContactConstraint& k = cons[static_cast<int>(c)];
    const ContactMode m = modes[c];
    if (m == ContactMode::Separating) continue;  // fixed at 0
    std::vector<std::pair<int, double>> col{{k.normal_row, 1.0}};
    const bool sticking = m == ContactMode::Sticking || !k.has_friction();
    if (!sticking) col.emplace_back(k.tangent_row, (m == ContactMode::SlidingPlus ? 1.0 : -1.0) * k.mu);
    var_row.push_back(k.normal_row);
    columns.push_back(col);
    if (sticking && k.has_friction()) {
      var_row.push_back(k.tangent_row);
      columns.push_back({{k.tangent_row, 1.0}});
    }
  }
  const int n = static_cast<int>(var_row.size());
  if (n == 0) return Eigen::VectorXd::Zero(rows);  // every contact separates
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(rows, n);
  for (int j = 0; j < n; ++j)
    for (const auto& [r, a] : columns[static_cast<std::size_t>(j)]) L(r, j) = a;
  Eigen::VectorXd xb(n);
  for (int j = 0; j < n; ++j) xb[j] = base[var_row[static_cast<std::size_t>(j)]];

  // S A L and the right-hand side −S (A L x_b + b), A = J (Δt M⁻¹) Jᵀ.
  const Eigen::MatrixXd JL = Eigen::MatrixXd(p.J.transpose()) * L;  // 3·bodies × n
  const Eigen::MatrixXd AL = Eigen::MatrixXd(p.J) * ((p.inv_mass * p.dt).asDiagonal() * JL);
  Eigen::MatrixXd SAL(n, n);
  Eigen::VectorXd rhs(n);
  const Eigen::VectorXd wb = AL * xb + p.b;
  for (int i = 0; i < n; ++i) {
    const int r = var_row[static_cast<std::size_t>(i)];
    SAL.row(i) = AL.row(r);
    rhs[i] = -wb[r];
  }
  const Eigen::VectorXd y = min_norm_solve(SAL, rhs, kActiveSetRankThreshold);
  Eigen::VectorXd out = L * (xb + y);
  project_feasible(p, out);
  return out;
}

}  // namespace dc
