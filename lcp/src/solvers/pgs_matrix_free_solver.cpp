// "pgs": the engine's default solver, matrix-free projected Gauss–Seidel on body velocities.
// Its sweep (kernels, segments, cost model) is MatrixFreeSweep (pgs_matrix_free.cpp); this file
// is the LcpSolver around it: input checks, the sweep driver, the assembled form for problems
// without J.
#include <string>
#include <vector>

#include "solvers/matrix_free_sweep.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers {
namespace {

class PgsMatrixFreeSolver final : public LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "pgs"; }
  [[nodiscard]] bool needs_jacobian() const override { return true; }
  [[nodiscard]] bool needs_assembled_matrix() const override { return false; }
  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) override {
    if (!p.has_jacobian()) {
      // A problem from a file has only A: run the same iteration in its assembled form.
      SolveResult r = solve_assembled_gauss_seidel(p, lambda0, o, 1.0, name());
      if (r.status != SolveStatus::InvalidInput)
        r.message = "no Jacobian in the problem: ran the assembled form of PGS" +
                    (r.message.empty() ? std::string() : "; " + r.message);
      return r;
    }
    Eigen::VectorXd lambda;
    if (auto bad = check_input(p, lambda0, name(), lambda)) return *bad;
    MatrixFreeSweep sweeper;
    if (std::string err = sweeper.prepare(p, o.block_manifolds); !err.empty())
      return refuse_matrix_free(p, lambda, "pgs", err);
    std::vector<double> du = sweeper.velocity_change(p, lambda);
    SolveResult r = run_sweeps(p, std::move(lambda), o, [&](Eigen::VectorXd& l, bool& nonfinite) {
      return sweeper.sweep(l.data(), du.data(), nonfinite);
    });
    report_singular_rows(p, sweeper.singular_rows(), r);
    finish(p, r, o, StopRule::Tolerance);
    return r;
  }
};

}  // namespace

std::unique_ptr<LcpSolver> make_pgs_matrix_free() { return std::make_unique<PgsMatrixFreeSolver>(); }

}  // namespace dc::solvers
