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
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc::solvers {
namespace {

/// The NNCG state between sweeps: direction p (and its Δu image pu), the sweep's starting point,
/// and the factor of the next move. `velocity_entries` = 0: no Δu
/// (assembled form). Two passes over the rows per iteration besides the sweep: after it, θ and
/// ‖Δf‖²; before the next, the direction update and the move fused in one loop.
class NncgMomentum {
 public:
  NncgMomentum(int rows, int velocity_entries)
      : p_(static_cast<size_t>(rows), 0.0), start_(p_),
        pu_(static_cast<size_t>(velocity_entries), 0.0), start_u_(pu_) {}

  /// Before a sweep: p ← β p + Δf (or 0 after a restart), λ += β p_old (Δu too), and the
  /// sweep's starting point.
  void before_sweep(double* lam, double* du) {
    const double beta = beta_;
    const bool keep = next_ != Next::Restart;
    for (size_t i = 0; i < p_.size(); ++i) {
      const double m = beta * p_[i];
      p_[i] = keep ? m + (lam[i] - start_[i]) : 0.0;
      lam[i] += m;
      start_[i] = lam[i];
    }
    for (size_t i = 0; i < pu_.size(); ++i) {
      const double m = beta * pu_[i];
      pu_[i] = keep ? m + (du[i] - start_u_[i]) : 0.0;
      du[i] += m;
      start_u_[i] = du[i];
    }
  }

  /// After the sweep: θ_k = max_i |Δf_k,i| [N], the sweep's change from its own starting
  /// point (the move excluded), and the factor of the next move, β = ‖Δf_k‖²/‖Δf_{k−1}‖², or a restart when β > 1.
  double after_sweep(const double* lam) {
    // Four partial sums and maxima (rows i ≡ j mod 4), combined in a fixed order: a single
    // running sum would put one add latency per row on a dependency chain, and the order stays
    // the same on every build.
    double th0 = 0, th1 = 0, th2 = 0, th3 = 0, sq0 = 0, sq1 = 0, sq2 = 0, sq3 = 0;
    const size_t n = p_.size();
    auto at = [&](size_t i, double& th, double& sq) {
      const double df = lam[i] - start_[i];
      th = std::max(th, std::abs(df));
      sq += df * df;
    };
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
      at(i, th0, sq0);
      at(i + 1, th1, sq1);
      at(i + 2, th2, sq2);
      at(i + 3, th3, sq3);
    }
    for (; i < n; ++i) at(i, th0, sq0);
    double theta = std::max(std::max(th0, th1), std::max(th2, th3));
    const double norm2 = (sq0 + sq1) + (sq2 + sq3);
    if (!std::isfinite(norm2)) theta = norm2;  // let the driver see the non-finite change
    if (next_ == Next::First) {
      // p_1 = Δf_1 (taken in the next before_sweep with β = 0): no move yet.
      next_ = Next::Momentum;
      beta_ = 0.0;
    } else {
      // A zero previous change (solved exactly) restarts, as in Bullet.
      const double beta = prev_norm2_ > 0 ? norm2 / prev_norm2_ : 2.0;
      if (beta > 1.0) {
        ++restarts_;
        beta_ = 0.0;
        next_ = Next::Restart;
      } else {
        beta_ = beta;
        next_ = Next::Momentum;
      }
    }
    prev_norm2_ = norm2;
    return theta;
  }

  [[nodiscard]] int restarts() const { return restarts_; }

 private:
  enum class Next { First, Momentum, Restart };
  std::vector<double> p_, start_;  // per row [N]
  std::vector<double> pu_, start_u_;      // per Δu entry [m/s, rad/s]
  double prev_norm2_ = 0.0, beta_ = 0.0;
  Next next_ = Next::First;
  int restarts_ = 0;
};

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
