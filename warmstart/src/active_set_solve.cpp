// The LCP solved on a given active set (active_set_solve.hpp; docs/bench.md). Per contact:
// Separating λ_n = λ_t = 0; Sticking λ_n, λ_t free with w_n = w_t = 0; Sliding ± λ_n free,
// λ_t = ±μ λ_n, w_n = 0. With the free variables x and λ = L x the equations are S A L x = −S b
// (S selects the free rows), singular where the pile is statically indeterminate; the guess is
// the solution nearest base's free values x_b,
//     x = x_b + argmin ‖y‖  s.t.  S A L y = −S (A L x_b + b)   (least squares if inconsistent)
// by a complete orthogonal decomposition of the dense S A L, then λ⁰ = project(L x). The
// strict inequalities (λ_n > 0, |λ_t| < μ λ_n, w ≥ 0) are enforced by the projection alone.
#include "dc/warmstart/active_set_solve.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_problem.hpp"
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
  // two ranks differed: the guess then depended on what the allocator handed out (docs/design.md §9).
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(M.rows(), M.cols());
  cod.setThreshold(threshold);
  cod.compute(M);
  return cod.solve(rhs);
}

namespace {

/// The free variables of an active set and the columns of L (≤ 2 entries each: a normal row,
/// and for a sliding contact its tangent row with ±μ).
struct ActiveSetVariables {
  std::vector<int> row;  ///< variable → its row (and its equation's row)
  std::vector<std::vector<std::pair<int, double>>> column;

  int size() const { return static_cast<int>(row.size()); }
  /// v at the variables' rows: x_b = gather(base), and S v of a vector v over the rows.
  Eigen::VectorXd gather(const Eigen::VectorXd& v) const {
    Eigen::VectorXd out(size());
    for (int j = 0; j < size(); ++j) out[j] = v[row[static_cast<std::size_t>(j)]];
    return out;
  }
  /// λ = L x (rows entries).
  Eigen::VectorXd lift(const Eigen::VectorXd& x, int rows) const {
    Eigen::VectorXd l = Eigen::VectorXd::Zero(rows);
    for (int j = 0; j < size(); ++j)
      for (const auto& [r, a] : column[static_cast<std::size_t>(j)]) l[r] += a * x[j];
    return l;
  }
};

ActiveSetVariables active_set_variables(const World& w, const std::vector<ContactMode>& modes, const char* who) {
  if (modes.size() != w.contacts().size()) throw InvalidArgument(std::string(who) + ": one mode per contact expected");
  const ContactConstraints& cons = w.constraints();
  ActiveSetVariables v;
  for (std::size_t c = 0; c < w.contacts().size(); ++c) {
    const ContactConstraint& k = cons[static_cast<int>(c)];
    const ContactMode m = modes[c];
    if (m == ContactMode::Separating) continue;  // fixed at 0
    std::vector<std::pair<int, double>> col{{k.normal_row, 1.0}};
    const bool sticking = m == ContactMode::Sticking || !k.has_friction();
    if (!sticking) col.emplace_back(k.tangent_row, (m == ContactMode::SlidingPlus ? 1.0 : -1.0) * k.mu);
    v.row.push_back(k.normal_row);
    v.column.push_back(col);
    if (sticking && k.has_friction()) {
      v.row.push_back(k.tangent_row);
      v.column.push_back({{k.tangent_row, 1.0}});
    }
  }
  return v;
}

}  // namespace

Eigen::VectorXd solve_on_active_set(const World& w, const Eigen::VectorXd& base,
                                    const std::vector<ContactMode>& modes, const char* who) {
  const LcpProblem& p = w.problem();
  require_dense_diagnostic_size(p, who);
  const ActiveSetVariables vars = active_set_variables(w, modes, who);
  const int rows = p.rows();
  const int n = vars.size();
  if (n == 0) return Eigen::VectorXd::Zero(rows);  // every contact separates
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(rows, n);
  for (int j = 0; j < n; ++j)
    for (const auto& [r, a] : vars.column[static_cast<std::size_t>(j)]) L(r, j) = a;
  const Eigen::VectorXd xb = vars.gather(base);

  // S A L and the right-hand side −S (A L x_b + b), A = J (Δt M⁻¹) Jᵀ.
  const Eigen::MatrixXd JL = Eigen::MatrixXd(p.J.transpose()) * L;  // 3·bodies × n
  const Eigen::MatrixXd AL = Eigen::MatrixXd(p.J) * ((p.inv_mass * p.dt).asDiagonal() * JL);
  Eigen::MatrixXd SAL(n, n);
  Eigen::VectorXd rhs(n);
  const Eigen::VectorXd wb = AL * xb + p.b;
  for (int i = 0; i < n; ++i) {
    const int r = vars.row[static_cast<std::size_t>(i)];
    SAL.row(i) = AL.row(r);
    rhs[i] = -wb[r];
  }
  const Eigen::VectorXd y = min_norm_solve(SAL, rhs, kActiveSetRankThreshold);
  Eigen::VectorXd out = L * (xb + y);
  project_feasible(p, out);
  return out;
}

Eigen::VectorXd solve_on_active_set_cgls(const World& w, const Eigen::VectorXd& base,
                                         const std::vector<ContactMode>& modes, int iterations, const char* who) {
  const LcpProblem& p = w.problem();
  if (!p.has_jacobian()) throw InvalidArgument(std::string(who) + ": the problem has no Jacobian");
  if (iterations < 1) throw InvalidArgument(std::string(who) + ": at least one CGLS iteration expected");
  const ActiveSetVariables vars = active_set_variables(w, modes, who);
  const int rows = p.rows();
  const int n = vars.size();
  if (n == 0) return Eigen::VectorXd::Zero(rows);
  const Eigen::VectorXd xb = vars.gather(base);
  // B y = S A L y and Bᵀ z = Lᵀ A Sᵀ z (A is symmetric), each one matrix-free A product.
  auto B = [&](const Eigen::VectorXd& y) { return vars.gather(lcp_apply(p, vars.lift(y, rows))); };
  auto Bt = [&](const Eigen::VectorXd& z) {
    Eigen::VectorXd spread = Eigen::VectorXd::Zero(rows);
    for (int i = 0; i < n; ++i) spread[vars.row[static_cast<std::size_t>(i)]] = z[i];
    const Eigen::VectorXd a = lcp_apply(p, spread);
    Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
    for (int j = 0; j < n; ++j)
      for (const auto& [r, c] : vars.column[static_cast<std::size_t>(j)]) out[j] += c * a[r];
    return out;
  };
  // Residual of the active-set equations at x_b: r = −S (A L x_b + b).
  Eigen::VectorXd r = -vars.gather(lcp_velocity(p, vars.lift(xb, rows)));
  // CGLS from y = 0: its iterates stay in range(Bᵀ), so it tends to the minimum-norm
  // least-squares solution (the dense path's answer) without forming B.
  Eigen::VectorXd y = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd s = Bt(r);
  Eigen::VectorXd d = s;
  double gamma = s.squaredNorm();
  const double stop = 1e-24 * std::max(gamma, 1e-300);
  for (int k = 0; k < iterations && gamma > stop; ++k) {
    const Eigen::VectorXd q = B(d);
    const double qq = q.squaredNorm();
    if (!(qq > 0)) break;
    const double alpha = gamma / qq;
    y += alpha * d;
    r -= alpha * q;
    s = Bt(r);
    const double next = s.squaredNorm();
    d = s + (next / gamma) * d;
    gamma = next;
  }
  Eigen::VectorXd out = vars.lift(xb + y, rows);
  project_feasible(p, out);
  return out;
}

// builtin-active's active set: a remembered contact keeps the mode of builtin's λ (`base`); a
// new one sticks when closing (gap ≤ slop + margin) and separates otherwise.
std::vector<ContactMode> remembered_modes(const World& w, const Eigen::VectorXd& base) {
  const std::size_t n = w.contacts().size();
  std::vector<ContactMode> modes(n);
  const std::vector<int> match = match_contacts_by_key(w.previous_contacts(), w.contacts());
  const double closing = w.def().contact.slop + w.def().contact.margin;
  for (std::size_t c = 0; c < n; ++c) {
    if (match[c] < 0)
      modes[c] = w.contacts()[c].gap <= closing ? ContactMode::Sticking : ContactMode::Separating;
    else
      modes[c] = contact_mode(w.constraints(), static_cast<int>(c), base);
  }
  return modes;
}


}  // namespace dc
