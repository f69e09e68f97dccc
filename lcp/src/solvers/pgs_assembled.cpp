// "pgs-assembled": projected Gauss–Seidel on the sparse row-major A, exactly the seed's
// iteration (docs/design.md §2). Also the implementation behind "psor" (ω ≠ 1).
#include "solvers/assembled_sweep.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers {

SolveResult solve_assembled_gauss_seidel(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                         const SolverOptions& o, double omega,
                                         const std::string& name) {
  std::optional<LcpProblem> local;
  const LcpProblem& p = with_assembled_matrix(problem, local);
  Eigen::VectorXd lambda;
  if (auto bad = check_input(p, lambda0, name, lambda)) return *bad;
  const AssembledSweep kernel(p);
  SolveResult r = run_sweeps(p, std::move(lambda), o, [&](Eigen::VectorXd& l, bool& nonfinite) {
    return kernel.sweep(l, omega, nonfinite);
  });
  report_singular_rows(p, kernel.singular_rows(), r);
  finish(p, r, o, StopRule::Tolerance);
  return r;
}

namespace {
class PgsAssembledSolver final : public LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "pgs-assembled"; }
  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) override {
    return solve_assembled_gauss_seidel(p, lambda0, o, 1.0, name());
  }
};
}  // namespace

std::unique_ptr<LcpSolver> make_pgs_assembled() { return std::make_unique<PgsAssembledSolver>(); }

}  // namespace dc::solvers
