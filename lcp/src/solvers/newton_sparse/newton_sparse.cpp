// "newton-sparse" (dc/lcp/newton_sparse.hpp): the iteration, its globalisation and status.
//
// Iteration k at λ (H, w evaluated there):
//   1. optional PGS smoothing sweeps;
//   2. modes and known moves (natural_map.hpp), the reduced system on the free rows
//        (A_FF + ρI + A_FC S) Δ_F = −w_F − A_FC d_C,
//      solved with the CHOLMOD factor of P = A_FF + ρI alone when no sliding friction row is
//      coupled (S = 0: P is the system), else by GMRES on the full operator preconditioned
//      with P⁻¹ (gmres.hpp);
//   3. line search on the merit φ = ½‖H‖² along the projected path λ(α) = proj(λ + αΔ),
//      α = 1, ½, ¼, … (Armijo: φ(λ(α)) ≤ (1 − 2σα) φ(λ)); if no α qualifies, PGS sweeps instead
//      (a sweep never increases the box-QP energy and moves the active set).
// φ is the unregularised natural map, so the iterate the solver returns is judged on the
// original problem, whatever ρ was.
#include <Eigen/SparseLU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "dc/lcp/newton_sparse.hpp"
#include "dc/core/error.hpp"
#include "solvers/assembled_sweep.hpp"
#include "dc/core/number_text.hpp"
#include "solvers/exact/box_newton.hpp"
#include "solvers/newton_sparse/gmres.hpp"
#include "solvers/newton_sparse/merit_window.hpp"
#include "solvers/newton_sparse/natural_map.hpp"
#include "solvers/newton_sparse/row_product.hpp"
#include "solvers/newton_sparse/sparse_factor.hpp"
#include "solvers/nncg_momentum.hpp"
#include "solvers/solver_common.hpp"

namespace dc {

struct NewtonSparseSolver::State {
  explicit State(const NewtonSparseDef& d) : factor(d.cholmod, d.reuse_analysis, d.supernodal) {}
  solvers::FreeBlockFactor factor;
  NewtonSparseStats last;
};

namespace solvers {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// One solve's Newton machinery on a validated problem with compressed A.
class NewtonStep {
 public:
  NewtonStep(const LcpProblem& p, const NewtonSparseDef& def, FreeBlockFactor& factor, NewtonSparseStats& st)
      : p_(p), def_(def), factor_(factor), st_(st), n_(p.rows()) {
    double maxdiag = 0.0;
    for (int i = 0; i < n_; ++i) maxdiag = std::max(maxdiag, p.A.coeff(i, i));
    diag_ = maxdiag > 0.0 ? maxdiag : 1.0;
    rho_min_ = rho_ = def.regularization * diag_;
    scale_ = 1.0 / rhs_scale(p);
  }

  /// Levenberg–Marquardt damping after a failed line search: ρ ← 100 ρ, at most
  /// max_damping·max_i A_ii. False when ρ is already there.
  bool damp() {
    if (rho_ >= def_.max_damping * diag_) return false;
    rho_ = std::min(rho_ * 100.0, def_.max_damping * diag_);
    ++st_.dampings;
    return true;
  }
  /// After a full step: ρ ← max(ρ_min, ρ/10).
  void relax() { rho_ = std::max(rho_min_, 0.1 * rho_); }

  /// The merit's scale s (evaluate_natural_map) of this solve.
  [[nodiscard]] double scale() const { return scale_; }

  /// Newton direction Δ at λ. False when no factorisation of the free block succeeded.
  bool direction(const Eigen::VectorXd& lambda, const NaturalMapValue& v, Eigen::VectorXd& delta) {
    linearize(p_, lambda, v, lin_);
    set_forcing(v);
    delta = lin_.known;
    if (lin_.free_count == 0) return true;
    // rhs_F = −w_F − (A d)_F; rhs_C = 0.
    Eigen::VectorXd rhs = p_.A * lin_.known;
    for (int i = 0; i < n_; ++i) rhs[i] = lin_.free[static_cast<size_t>(i)] ? -v.w[i] - rhs[i] : 0.0;
    Eigen::VectorXd x;
    if (!lin_.couplings.empty() && def_.coupled_lu && coupled_lu_solve(rhs, x)) {
      // the exact non-symmetric system, factorised directly
    } else if (stale_solve(rhs, x)) {
      // GMRES with the kept factor met its tolerance
    } else if (!factor_.factorize(lin_.free, rho_, st_)) {
      return false;
    } else {
      krylov_or_direct(rhs, x);
    }
    if (!x.allFinite()) return false;
    for (int i = 0; i < n_; ++i)
      if (lin_.free[static_cast<size_t>(i)]) delta[i] = x[i];
    for (const FrictionCoupling& c : lin_.couplings) delta[c.row] += c.slope * x[c.normal];
    return true;
  }

  /// GMRES on the full Newton system preconditioned with the factor kept from an earlier
  /// factorisation (NewtonSparseDef::stale_factor_iterations); true when it met η_k within that
  /// many iterations, or came within stale_accept·η_k (x is then the direction), false to
  /// refactorise.
  bool stale_solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
    x.resize(0);  // no start for krylov_or_direct unless a stale run below leaves one
    if (def_.stale_factor_iterations <= 0 || !factor_.factored()) return false;
    const auto t0 = Clock::now();
    const LinearMap K = [this](const Eigen::VectorXd& in, Eigen::VectorXd& out) { apply_system(in, out); };
    const LinearMap Pinv = [this](const Eigen::VectorXd& in, Eigen::VectorXd& out) { factor_.solve(in, out); };
    const KrylovOutcome k = gmres(K, Pinv, rhs, x, def_.krylov_restart, def_.stale_factor_iterations, eta_, dot());
    st_.krylov_iterations += k.iterations;
    st_.solve_ms += ms_since(t0);
    const bool near = k.converged || k.relative_residual <= def_.stale_accept * eta_;  // stale_accept
    if (!near || !x.allFinite()) return false;
    ++st_.stale_directions;
    return true;
  }

  /// With the CHOLMOD factor of P: P⁻¹ rhs when nothing is coupled (P is the system), else GMRES
  /// from x when x holds a failed stale run's answer (same K and rhs; its ‖rhs − K x‖ is within a
  /// small multiple of η_k·‖rhs‖, so the fresh run only has to remove that multiple), from zero
  /// when x is empty.
  void krylov_or_direct(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
    const auto t0 = Clock::now();
    if (lin_.couplings.empty()) {
      factor_.solve(rhs, x);
    } else {
      const LinearMap K = [this](const Eigen::VectorXd& in, Eigen::VectorXd& out) { apply_system(in, out); };
      const LinearMap Pinv = [this](const Eigen::VectorXd& in, Eigen::VectorXd& out) { factor_.solve(in, out); };
      st_.krylov_iterations += gmres_from(K, Pinv, rhs, x, def_.krylov_restart, def_.krylov_max, eta_, dot()).iterations;
    }
    st_.solve_ms += ms_since(t0);
  }

  /// The full-size Newton matrix K (free rows: A_FF + ρI with the coupling ±μ A_it moved to the
  /// normal column; clamped rows: identity) factorised by sparse LU. False when LU fails.
  bool coupled_lu_solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
    const auto t0 = Clock::now();
    coupled_of_.assign(static_cast<size_t>(n_), -1);
    for (size_t k = 0; k < lin_.couplings.size(); ++k) coupled_of_[static_cast<size_t>(lin_.couplings[k].row)] = static_cast<int>(k);
    trip_.clear();
    for (int i = 0; i < n_; ++i) {
      if (!lin_.free[static_cast<size_t>(i)]) {
        trip_.emplace_back(i, i, 1.0);
        continue;
      }
      trip_.emplace_back(i, i, rho_);
      for (SparseRowMatrix::InnerIterator e(p_.A, i); e; ++e) {
        const int j = static_cast<int>(e.col());
        if (lin_.free[static_cast<size_t>(j)]) {
          trip_.emplace_back(i, j, e.value());
        } else if (const int k = coupled_of_[static_cast<size_t>(j)]; k >= 0) {
          const FrictionCoupling& c = lin_.couplings[static_cast<size_t>(k)];
          trip_.emplace_back(i, c.normal, c.slope * e.value());
        }
      }
    }
    Eigen::SparseMatrix<double> K(n_, n_);
    K.setFromTriplets(trip_.begin(), trip_.end());
    K.makeCompressed();
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    lu.analyzePattern(K);
    lu.factorize(K);
    ++st_.factorizations;
    ++st_.lu_factorizations;
    st_.factor_ms += ms_since(t0);
    if (lu.info() != Eigen::Success) return false;
    const auto t1 = Clock::now();
    x = lu.solve(rhs);
    st_.solve_ms += ms_since(t1);
    return x.allFinite();
  }

  /// Backtracking on φ along proj(λ + αΔ). On success λ and v move to the accepted point.
  bool line_search(Eigen::VectorXd& lambda, NaturalMapValue& v, const Eigen::VectorXd& delta, double& alpha,
                   double reference) {
    alpha = 1.0;
    for (int k = 0; k <= def_.max_backtracks; ++k, alpha *= 0.5) {
      trial_ = lambda + alpha * delta;
      project_onto_bounds(p_, trial_);
      evaluate_natural_map(p_, trial_, scale_, trial_value_);
      ++st_.line_search_trials;
      if (trial_value_.merit <= (1.0 - 2.0 * def_.armijo * alpha) * reference) {
        if (k == 0) ++st_.full_steps;
        lambda.swap(trial_);
        std::swap(v, trial_value_);
        return true;
      }
    }
    ++st_.failed_line_searches;
    return false;
  }

 private:
  /// GMRES's inner product (NewtonSparseDef::lane_dot).
  [[nodiscard]] Dot dot() const { return def_.lane_dot ? dot_in_lanes : dot_in_order; }

  /// GMRES's relative tolerance η_k for this direction (NewtonSparseDef::krylov_forcing):
  /// min(krylov_forcing, ‖H_k‖₂/‖H_0‖₂), at least krylov_tolerance; H_0 is the first
  /// direction's natural map of this solve.
  void set_forcing(const NaturalMapValue& v) {
    const double h = std::sqrt(dot_in_order(v.h, v.h));
    if (h0_ < 0.0) h0_ = h;
    eta_ = def_.krylov_tolerance;
    if (def_.krylov_forcing > 0.0 && h0_ > 0.0 && std::isfinite(h))
      eta_ = std::max(def_.krylov_tolerance, std::min(def_.krylov_forcing, h / h0_));
  }

  /// out = K in: (A u)_F + ρ in_F on free rows with u = in on F and u_t = s·in_n on the
  /// coupled friction rows; out_C = in_C (identity rows, rhs 0).
  void apply_system(const Eigen::VectorXd& in, Eigen::VectorXd& out) {
    u_ = in;
    for (int i = 0; i < n_; ++i)
      if (!lin_.free[static_cast<size_t>(i)]) u_[i] = 0.0;
    for (const FrictionCoupling& c : lin_.couplings) u_[c.row] = c.slope * in[c.normal];
    row_product(p_.A, u_, out);
    for (int i = 0; i < n_; ++i) out[i] = lin_.free[static_cast<size_t>(i)] ? out[i] + rho_ * in[i] : in[i];
  }

  const LcpProblem& p_;
  const NewtonSparseDef& def_;
  FreeBlockFactor& factor_;
  NewtonSparseStats& st_;
  int n_;
  double diag_ = 1.0, rho_min_ = 0.0, rho_ = 0.0, scale_ = 1.0;
  double h0_ = -1.0, eta_ = 0.0;  // ‖H‖₂ at the first direction (−1: none yet); GMRES tolerance
  NewtonLinearization lin_;
  std::vector<int> coupled_of_;
  std::vector<Eigen::Triplet<double>> trip_;
  Eigen::VectorXd u_, trial_;
  NaturalMapValue trial_value_;
};

/// The iteration with its bookkeeping (best iterate, stalls, θ, checkpoints).
class NewtonSparseRun {
 public:
  NewtonSparseRun(const LcpProblem& p, const NewtonSparseDef& def, const SolverOptions& o, FreeBlockFactor& factor,
                  NewtonSparseStats& st)
      : p_(p), def_(def), o_(o), st_(st), step_(p, def, factor, st), cp_(o), window_(def.nonmonotone_window) {}

  SolveResult run(Eigen::VectorXd lambda, double target) {
    SolveResult r;
    project_onto_bounds(p_, lambda);
    evaluate_natural_map(p_, lambda, step_.scale(), v_);
    if (!std::isfinite(v_.merit)) {  // e.g. a huge guess overflowing A λ: restart from zero
      lambda.setZero();
      evaluate_natural_map(p_, lambda, step_.scale(), v_);
      r.message = "non-finite natural map at the guess; started from zero";
    }
    best_ = lambda;
    best_res_ = v_.max_abs;
    window_.push(v_.merit);
    const int max_iter = std::max(0, o_.max_sweeps);
    int stalls = 0;
    // Why the loop ended: only the iteration limit is a SweepLimit, the others are failures.
    // `why` says the same in words, for the message.
    enum class Stop { IterationLimit, NoFiniteIterate, Stalled, Requested } stop = Stop::IterationLimit;
    std::string why = "iteration limit";
    while (v_.max_abs > target) {
      if (st_.iterations >= max_iter) break;
      if (!iterate(lambda)) {
        stop = Stop::NoFiniteIterate;
        why = "no finite iterate";
        break;
      }
      if (v_.max_abs < best_res_) {
        best_res_ = v_.max_abs;
        best_ = lambda;
        stalls = 0;
        monotone_ = false;
      } else if (++stalls >= def_.max_stalls) {
        stop = Stop::Stalled;
        why = "stalled: no decrease of the residual in " + std::to_string(stalls) + " iterations";
        break;
      } else if (stalls == def_.nonmonotone_window && !monotone_) {
        // Watchdog: a window of non-monotone steps without a new best goes back to the best
        // iterate, and the line search stays monotone until it finds a new best.
        lambda = best_;
        evaluate_natural_map(p_, lambda, step_.scale(), v_);
        window_.clear();
        monotone_ = true;
      }
      if (def_.stop_when && def_.stop_when(st_.iterations, lambda)) {
        stop = Stop::Requested;
        why = "stopped by the caller";
        break;
      }
      if (slow_cap_) {
        stop = Stop::Stalled;
        why = "fallback sweeps at their cap lowered the residual less than fallback_cap_fall-fold";
        break;
      }
    }
    r.lambda = best_;
    r.sweeps = st_.iterations;
    const double residual = natural_residual(p_, r.lambda);
    if (residual <= target) {
      r.status = SolveStatus::Converged;
      cp_.flush_final(r.lambda);
    } else {
      r.status = stop == Stop::IterationLimit ? SolveStatus::SweepLimit : SolveStatus::Failed;
      r.message += (r.message.empty() ? "" : "; ") + why + ": residual " + g_text(residual) +
                   " N above target " + g_text(target) + " N";
    }
    // A target the caller gave (options.tolerance [N]) is a stopping rule, not the solution test.
    finish(p_, r, o_, o_.tolerance > 0 ? StopRule::Tolerance : StopRule::Solution);
    return r;
  }

 private:
  /// One iteration: smoothing, Newton step or fallback sweeps. False if λ became non-finite.
  bool iterate(Eigen::VectorXd& lambda) {
    ++st_.iterations;
    previous_ = lambda;
    if (def_.smoothing_sweeps > 0) sweeps(lambda, def_.smoothing_sweeps);
    // Newton step; when the line search fails, damp the free block (a shorter, better
    // conditioned step: the components of w_F outside range(A_FF), which the undamped step
    // amplifies by 1/ρ, shrink) and retry; PGS sweeps when even the damped step fails.
    bool stepped = false;
    double alpha = 0.0;
    while (step_.direction(lambda, v_, delta_)) {
      stepped = step_.line_search(lambda, v_, delta_, alpha, monotone_ ? v_.merit : window_.reference(v_.merit));
      if (stepped) {
        if (alpha == 1.0) step_.relax();
        break;
      }
      if (!step_.damp()) break;
    }
    // A failed or short step (α < 1/16: the modes are still far from right) is followed by PGS
    // sweeps, doubled after each further such iteration up to 2^fallback_doublings times: where
    // the modes are too degenerate for Newton (far more rows than body dofs) PGS carries the
    // iterate onwards.
    const bool good = stepped && alpha >= 1.0 / 16;
    failures_ = good ? 0 : failures_ + 1;
    slow_cap_ = false;
    if (!good) {
      const int doublings = std::clamp(std::min(failures_ - 1, def_.fallback_doublings), 0, 20);
      const int count = std::max(1, def_.fallback_sweeps) << doublings;
      const double before = v_.max_abs;
      sweeps(lambda, count, def_.fallback_momentum);
      // A batch at the cap that did not lower ‖H‖∞ fallback_cap_fall-fold: further batches
      // repeat it, a slow PGS solve (NewtonSparseDef::fallback_cap_fall).
      slow_cap_ = def_.fallback_cap_fall > 0 && doublings >= std::clamp(def_.fallback_doublings, 0, 20) &&
                  doublings > 0 && !(v_.max_abs <= def_.fallback_cap_fall * before);
    }
    if (!lambda.allFinite() || !std::isfinite(v_.merit)) {
      lambda = best_;
      evaluate_natural_map(p_, lambda, step_.scale(), v_);
      return false;
    }
    window_.push(v_.merit);
    const double theta = (lambda - previous_).cwiseAbs().maxCoeff();
    if (o_.record_theta) theta_.push_back(theta);
    cp_.after(st_.iterations, lambda);
    return true;
  }

  /// `count` PGS sweeps; with `momentum`, NNCG's (nncg_momentum.hpp) from a fresh direction.
  void sweeps(Eigen::VectorXd& lambda, int count, bool momentum = false) {
    if (!kernel_) kernel_.emplace(p_);
    bool nonfinite = false;
    std::optional<NncgMomentum> m;
    if (momentum) m.emplace(p_.rows(), 0);
    for (int s = 0; s < count && !nonfinite; ++s) {
      if (m) m->before_sweep(lambda.data(), nullptr);
      kernel_->sweep(lambda, 1.0, nonfinite);
      if (m) m->after_sweep(lambda.data());
      ++st_.pgs_sweeps;
    }
    evaluate_natural_map(p_, lambda, step_.scale(), v_);
  }

 public:
  std::vector<double> theta_;

 private:
  const LcpProblem& p_;
  const NewtonSparseDef& def_;
  const SolverOptions& o_;
  NewtonSparseStats& st_;
  NewtonStep step_;
  CheckpointCursor cp_;
  std::optional<AssembledSweep> kernel_;
  MeritWindow window_;
  bool monotone_ = false;  // the watchdog went back to the best iterate; no new best since
  NaturalMapValue v_;
  Eigen::VectorXd best_, previous_, delta_;
  double best_res_ = 0.0;
  int failures_ = 0;       // consecutive iterations without an accepted Newton step
  bool slow_cap_ = false;  // the last iteration's fallback batch was at the cap and slow
};

}  // namespace
}  // namespace solvers

NewtonSparseSolver::NewtonSparseSolver(const NewtonSparseDef& def)
    : def_(def), state_(std::make_unique<State>(def)) {
  if (!(def.fallback_cap_fall >= 0 && def.fallback_cap_fall <= 1))
    throw InvalidArgument("newton-sparse: fallback_cap_fall must be in [0, 1]");
  if (def.nonmonotone_window < 0) throw InvalidArgument("newton-sparse: nonmonotone_window must be >= 0");
  if (!(std::isfinite(def.stale_accept) && def.stale_accept >= 1))
    throw InvalidArgument("newton-sparse: stale_accept must be finite and >= 1");
}

NewtonSparseSolver::~NewtonSparseSolver() = default;

NewtonSparseStats NewtonSparseSolver::last_stats() const { return state_->last; }

SolveResult NewtonSparseSolver::solve(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                      const SolverOptions& o) {
  const auto t0 = solvers::Clock::now();
  // The counts grow in place: last_stats() from a checkpoint callback reads the solve so far.
  NewtonSparseStats& st = state_->last;
  st = {};
  std::optional<LcpProblem> local;
  const LcpProblem* p = &solvers::with_assembled_matrix(problem, local);
  Eigen::VectorXd lambda;
  if (auto bad = solvers::check_input(*p, lambda0, name(), lambda)) return *bad;
  if (!p->A.isCompressed()) {  // the factor's pattern key reads the compressed arrays
    if (!local) local.emplace(*p);
    local->A.makeCompressed();
    p = &*local;
  }
  const double target = o.tolerance > 0 ? o.tolerance : solution_target(*p, o);
  state_->factor.bind(p->A, solvers::is_symmetric(p->A));
  solvers::NewtonSparseRun run(*p, def_, o, state_->factor, st);
  SolveResult r = run.run(std::move(lambda), target);
  r.theta = std::move(run.theta_);
  st.total_ms = solvers::ms_since(t0);
  return r;
}

std::unique_ptr<LcpSolver> make_newton_sparse(const NewtonSparseDef& def) {
  return std::make_unique<NewtonSparseSolver>(def);
}

}  // namespace dc
