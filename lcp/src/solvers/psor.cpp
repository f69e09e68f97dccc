// "psor": projected successive over-relaxation on the assembled A,
//   λ_i ← proj(λ_i − ω r_i / A_ii),  ω = options.omega.
// ω = 1 is pgs-assembled bit for bit. For symmetric PSD A the iteration converges for
// 0 < ω < 2 (Cryer); other ω give InvalidInput.
#include <cmath>

#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"
#include "dc/core/number_text.hpp"

namespace dc::solvers {
namespace {
class PsorSolver final : public LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "psor"; }
  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) override {
    if (!(o.omega > 0 && o.omega < 2)) {
      SolveResult r;
      r.status = SolveStatus::InvalidInput;
      r.lambda = lambda0.size() == p.rows() && lambda0.allFinite() ? lambda0
                                                                   : Eigen::VectorXd::Zero(p.rows());
      r.message = "psor: relaxation omega = " + g_text(o.omega) + " is outside (0, 2)";
      r.residual = std::numeric_limits<double>::infinity();
      return r;
    }
    return solve_assembled_gauss_seidel(p, lambda0, o, o.omega, name());
  }
};
}  // namespace

std::unique_ptr<LcpSolver> make_psor() { return std::make_unique<PsorSolver>(); }

}  // namespace dc::solvers
