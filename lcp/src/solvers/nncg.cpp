// "nncg": nonsmooth nonlinear conjugate gradient (Silcowitz, Niebe, Erleben, The Visual
// Computer 26, 2010; Bullet's btNNCGConstraintSolver): PGS sweeps with Fletcher–Reeves
// momentum. Sweep change Δf_k = G(λ) − λ, β_k = ‖Δf_k‖²/‖Δf_{k−1}‖²; β_k > 1 restarts (p = 0:
// plain PGS), else p_k = β_k p_{k−1} + Δf_k and λ moves by β_k p_{k−1}. The move is applied at
// the start of the next sweep (the same sequence of sweeps as Bullet), so every returned,
// recorded or checkpointed λ is a projecting sweep's output (feasible), and θ_k = ‖Δf_k‖∞ is
// the sweep's own change, without the move: a move that cancels the sweep's change would
// otherwise show θ ≈ 0 away from a solution. One iteration = one "pgs" sweep (MatrixFreeSweep) plus
// O(rows + bodies): pu = M⁻¹ Jᵀ p Δt is kept as a vector, so no product with J. The sums ‖Δf‖²
// are explicit loops in a fixed order (bit-equal across builds). Without J the same method runs
// on the assembled sweep (assembled_sweep.hpp), the momentum on λ alone. docs/solvers.md "nncg".
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "solvers/assembled_sweep.hpp"
#include "solvers/matrix_free_sweep.hpp"
#include "solvers/nncg_momentum.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers {
namespace {

void note_restarts(const NncgMomentum& m, SolveResult& r) {
  r.message += (r.message.empty() ? "" : "; ") + std::to_string(m.restarts()) + " restart(s) of the CG direction";
}

/// NNCG on the assembled A (problems without J, e.g. read from a file).
SolveResult solve_assembled(const LcpProblem& problem, const Eigen::VectorXd& lambda0, const SolverOptions& o,
                            const SweepWatch* watch) {
  std::optional<LcpProblem> local;
  const LcpProblem& p = with_assembled_matrix(problem, local);
  Eigen::VectorXd lambda;
  if (auto bad = check_input(p, lambda0, "nncg", lambda)) return *bad;
  const AssembledSweep kernel(p);
  NncgMomentum momentum(p.rows(), 0);
  SolveResult r = run_sweeps(p, std::move(lambda), o, [&](Eigen::VectorXd& l, bool& nonfinite) {
    momentum.before_sweep(l.data(), nullptr);
    kernel.sweep(l, 1.0, nonfinite);
    return momentum.after_sweep(l.data());
  }, watch);
  r.message = "no Jacobian in the problem: ran the assembled form of NNCG" + (r.message.empty() ? "" : "; " + r.message);
  note_restarts(momentum, r);
  report_singular_rows(p, kernel.singular_rows(), r);
  finish(p, r, o, StopRule::Tolerance);
  return r;
}

class NncgSolver final : public LcpSolver {
 public:
  [[nodiscard]] std::string name() const override { return "nncg"; }
  [[nodiscard]] bool needs_jacobian() const override { return true; }
  [[nodiscard]] bool needs_assembled_matrix() const override { return false; }
  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) override {
    return nncg_solve(p, lambda0, o, nullptr);
  }
};

}  // namespace

SolveResult nncg_solve(const LcpProblem& p, const Eigen::VectorXd& lambda0, const SolverOptions& o,
                       const SweepWatch* watch) {
  if (!p.has_jacobian()) return solve_assembled(p, lambda0, o, watch);
  Eigen::VectorXd lambda;
  if (auto bad = check_input(p, lambda0, "nncg", lambda)) return *bad;
  MatrixFreeSweep sweeper;
  if (std::string err = sweeper.prepare(p, o.block_manifolds); !err.empty())
    return refuse_matrix_free(p, lambda, "nncg", err);
  std::vector<double> du = sweeper.velocity_change(p, lambda);
  NncgMomentum momentum(p.rows(), sweeper.body_entries());
  SolveResult r = run_sweeps(p, std::move(lambda), o, [&](Eigen::VectorXd& l, bool& nonfinite) {
    momentum.before_sweep(l.data(), du.data());
    sweeper.sweep(l.data(), du.data(), nonfinite);
    return momentum.after_sweep(l.data());
  }, watch);
  note_restarts(momentum, r);
  report_singular_rows(p, sweeper.singular_rows(), r);
  finish(p, r, o, StopRule::Tolerance);
  return r;
}

std::unique_ptr<LcpSolver> make_nncg() { return std::make_unique<NncgSolver>(); }

}  // namespace dc::solvers
