// "jacobi": damped projected Jacobi on the assembled A,
//   λ_i^{k+1} = proj_[lo_i(λ^k), hi_i(λ^k)](λ_i^k − ω r_i(λ^k) / A_ii),   ω = options.omega,
// every row from the previous iterate (friction bounds from the previous normal values).
// Unlike Gauss–Seidel it is only guaranteed to converge when ω·ρ(D⁻¹A) < 2; contact matrices
// J M⁻¹ Jᵀ Δt of piles have ρ(D⁻¹A) well above 2 (a body with many contacts couples them
// strongly), so with ω = 1 the iterates typically oscillate and grow: the driver then
// reports Diverged ("iterates grow without bound") or SweepLimit. ω ≈ 1/(max contacts per
// body) is a safe damping for contact problems.
#include <cmath>

#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"
#include "dc/core/number_text.hpp"

namespace dc::solvers {
namespace {
class JacobiSolver final : public LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "jacobi"; }
  [[nodiscard]] SolveResult solve(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) override {
    std::optional<LcpProblem> local;
    const LcpProblem& p = with_assembled_matrix(problem, local);
    Eigen::VectorXd lambda;
    if (auto bad = check_input(p, lambda0, name(), lambda)) return *bad;
    if (!(o.omega > 0 && o.omega <= 1)) {
      SolveResult r;
      r.status = SolveStatus::InvalidInput;
      r.lambda = lambda;
      r.message = "jacobi: damping omega = " + g_text(o.omega) + " is outside (0, 1]";
      finish(p, r, o, StopRule::Tolerance);
      return r;
    }
    const int n = p.rows();
    const RowBounds bounds(p);
    std::vector<double> inv_diag(static_cast<size_t>(n), 0.0);
    std::vector<int> singular;
    for (int i = 0; i < n; ++i) {
      const double d = p.A.coeff(i, i), inv = 1.0 / d;
      if (d > 0 && std::isfinite(inv))
        inv_diag[static_cast<size_t>(i)] = inv;
      else
        singular.push_back(i);
    }
    const double omega = o.omega;
    Eigen::VectorXd w(n);
    SolveResult r = run_sweeps(p, std::move(lambda), o, [&](Eigen::VectorXd& l, bool& nonfinite) {
      w.noalias() = p.A * l;
      w += p.b;
      const Eigen::VectorXd old = l;  // bounds and residuals from λ^k
      double theta = 0.0;
      for (int i = 0; i < n; ++i) {
        const auto u = static_cast<size_t>(i);
        const double t = bounds.mu[u] * std::max(0.0, old[bounds.coupled[u]]);
        const double lo = bounds.lo_fixed[u] - t, hi = bounds.hi_fixed[u] + t;
        const double inv = inv_diag[u];
        double x = inv > 0 ? old[i] - omega * w[i] * inv : singular_row_update(old[i], w[i], lo, hi);
        x = std::min(std::max(x, lo), hi);
        if (!std::isfinite(x)) nonfinite = true;
        l[i] = x;
        theta = std::max(theta, std::abs(x - old[i]));
      }
      return theta;
    });
    report_singular_rows(p, singular, r);
    if (r.status == SolveStatus::SweepLimit && o.tolerance > 0 && omega == 1.0)
      r.message += (r.message.empty() ? "" : "; ") +
                   std::string("undamped Jacobi (omega = 1) need not converge on contact problems; "
                               "try omega < 1");
    finish(p, r, o, StopRule::Tolerance);
    return r;
  }
};
}  // namespace

std::unique_ptr<LcpSolver> make_jacobi() { return std::make_unique<JacobiSolver>(); }

}  // namespace dc::solvers
