// "newton": minimum-map Newton for box-bounded and frictional LCPs, the exact "oracle".
//
// Outer passes k = 0, 1, …: freeze the friction bounds at the current normal values
// (hi_t = μ max(0, λ_n), lo_t = −hi_t) and solve the resulting box LCP w = Aλ + b,
// lo ≤ λ ≤ hi with the globalised min-map Newton of box_newton.hpp from the current λ.
// Without friction one pass is the whole solve. With friction the staggered passes converge
// in a handful of passes on contact problems, each warm-started from the previous one.
//
// Stops when the natural residual of the original problem is ≤ exact_tolerance·max(1,‖b‖∞)
// (Converged). If Newton stalls (repeated line-search or factorisation failures, pass or
// step limit) a PGS polish of up to 20000 sweeps continues from the best iterate and the
// message says so; the status is Converged if the polish reaches the tolerance, Failed if
// not. `sweeps` counts Newton iterations plus polish sweeps; θ_k is the max change of λ in
// iteration/sweep k. Failing proves nothing: the status is Infeasible only when a standard
// LCP (n ≤ 500) has a verified Farkas certificate (lcp_proofs.hpp), never otherwise.
#include <cmath>

#include "solvers/assembled_sweep.hpp"
#include "solvers/exact/box_newton.hpp"
#include "dc/core/number_text.hpp"
#include "solvers/exact/lcp_proofs.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers {
namespace {

class NewtonSolver final : public LcpSolver {
 public:
  /// seek_certificate: see newton_solve (solvers.hpp).
  explicit NewtonSolver(bool seek_certificate) : seek_certificate_(seek_certificate) {}
  [[nodiscard]] std::string name() const override { return "newton"; }
  [[nodiscard]] SolveResult solve(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                  const SolverOptions& o) override {
    std::optional<LcpProblem> local;
    const LcpProblem& p = with_assembled_matrix(problem, local);
    Eigen::VectorXd lambda;
    if (auto bad = check_input(p, lambda0, name(), lambda)) return *bad;
    const int n = p.rows();
    const double target = solution_target(p, o);
    const int max_steps = std::max(1, o.max_sweeps);
    SolveResult r;
    r.status = SolveStatus::Failed;
    CheckpointCursor cp(o);

    double maxdiag = 0.0, maxabs = 0.0;
    for (int k = 0; k < p.A.outerSize(); ++k)
      for (SparseRowMatrix::InnerIterator it(p.A, k); it; ++it) {
        maxabs = std::max(maxabs, std::abs(it.value()));
        if (it.row() == it.col()) maxdiag = std::max(maxdiag, it.value());
      }
    const double rho = 1e-10 * (maxdiag > 0 ? maxdiag : (maxabs > 0 ? maxabs : 1.0));
    const bool symmetric = is_symmetric(p.A);
    bool friction = false;
    for (int i = 0; i < n; ++i) friction = friction || p.is_friction_row(i);

    Eigen::VectorXd lo(n), hi(n), best = lambda;
    double best_res = natural_residual(p, lambda);
    int steps = 0;
    std::string why;
    auto on_step = [&](const Eigen::VectorXd& l, double step) {
      ++steps;
      if (o.record_theta) r.theta.push_back(step);
      cp.after(steps, l);
    };
    if (best_res <= target) {
      r.status = SolveStatus::Converged;
    } else {
      const int max_passes = friction ? 100 : 1;
      int stalls = 0;
      const Eigen::VectorXd b(p.b);  // BoxNewtonSystem holds a VectorXd reference
      for (int pass = 0; pass < max_passes && steps < max_steps; ++pass) {
        for (int i = 0; i < n; ++i) {
          lo[i] = p.lower(i, lambda);
          hi[i] = p.upper(i, lambda);
        }
        const BoxNewtonSystem sys{p.A, symmetric, rho, b, lo, hi};
        Eigen::VectorXd trial = lambda;
        const BoxNewtonOutcome out =
            box_newton(sys, trial, 0.1 * target, std::min(friction ? 100 : 500, max_steps - steps), on_step);
        if (!trial.allFinite()) {
          why = "Newton iterate became non-finite";
          break;
        }
        const double res = natural_residual(p, trial);
        const double moved = (trial - lambda).cwiseAbs().maxCoeff();
        lambda = trial;
        if (res < best_res) {
          best_res = res;
          best = lambda;
        }
        if (res <= target) {
          r.status = SolveStatus::Converged;
          break;
        }
        if (!out.converged) {
          why = out.why;
          if (++stalls >= 3) break;
        }
        if (moved == 0.0 && out.converged) {
          why = "fixed point reached above tolerance (round-off floor)";
          break;
        }
      }
      if (r.status != SolveStatus::Converged && why.empty()) why = "pass/step limit reached";
    }
    lambda = best;
    if (r.status != SolveStatus::Converged) {
      // PGS polish from the best Newton iterate; checks the true residual every 50 sweeps.
      const AssembledSweep kernel(p);
      int polish = 0;
      bool nonfinite = false;
      Eigen::VectorXd last = lambda;
      while (polish < 20000 && !nonfinite) {
        for (int s = 0; s < 50; ++s) {
          last = lambda;
          const double th = kernel.sweep(lambda, 1.0, nonfinite);
          if (nonfinite) {
            lambda = last;
            break;
          }
          ++polish;
          if (o.record_theta) r.theta.push_back(th);
        }
        if (natural_residual(p, lambda) <= target) break;
      }
      const double res = natural_residual(p, lambda);
      if (res < best_res) {
        best_res = res;
        best = lambda;
      }
      lambda = best;
      steps += polish;
      if (best_res <= target) {
        r.status = SolveStatus::Converged;
        r.message = "newton stalled (" + why + "); a PGS polish of " + std::to_string(polish) +
                    " sweeps reached the tolerance";
      } else {
        r.status = SolveStatus::Failed;
        r.message = "newton stalled (" + why + ") and a PGS polish of " + std::to_string(polish) +
                    " sweeps did not reach residual " + g_text(target) +
                    " (best " + g_text(best_res) + ")";
      }
    }
    if (r.status == SolveStatus::Converged) cp.flush_final(lambda);
    if (r.status == SolveStatus::Failed && seek_certificate_ && n <= kFarkasMaxN && first_nonstandard_row(p) < 0) {
      // Failing proves nothing; a verified Farkas certificate proves that there is no solution.
      const FarkasCertificate cert = find_farkas_certificate(Eigen::MatrixXd(p.A), Eigen::VectorXd(p.b));
      if (cert.found) r.status = SolveStatus::Infeasible;
      r.message += (cert.found ? "; infeasible: " : "; ") + cert.detail;
    }
    r.sweeps = steps;
    r.lambda = lambda;
    finish(p, r, o, StopRule::Solution);
    return r;
  }

 private:
  bool seek_certificate_;
};

}  // namespace

SolveResult newton_solve(const LcpProblem& p, const Eigen::VectorXd& lambda0, const SolverOptions& o,
                         bool seek_certificate) {
  return NewtonSolver(seek_certificate).solve(p, lambda0, o);
}

std::unique_ptr<LcpSolver> make_newton() { return std::make_unique<NewtonSolver>(true); }

}  // namespace dc::solvers
