#pragma once
// Private helpers shared by the LCP solver family (lcp/src/solvers/*.cpp): input checks,
// the checkpoint cursor, the generic sweep driver of the iterative methods and the row
// bounds in the branch-free form the sweep kernels use. Not part of the public API.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dc/core/number_text.hpp"
#include "dc/lcp/lcp_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace dc::solvers {

/// The problem with A present: `p` itself when it has A (or has no J to form it from),
/// otherwise a copy of p in `local` with A = J M⁻¹ Jᵀ Δt formed. For the assembled solvers.
const LcpProblem& with_assembled_matrix(const LcpProblem& p, std::optional<LcpProblem>& local);

/// max(1, ‖b‖∞): the scale the exact tolerances are relative to.
double rhs_scale(const LcpProblem& p);

/// The first row that is not a standard LCP row (lo = 0, hi = +∞, no friction), or −1.
int first_nonstandard_row(const LcpProblem& p);

/// Validates the problem and the initial guess. On success returns std::nullopt and sets
/// `lambda` to λ⁰ (an empty λ⁰ means zero). On failure returns a result with status
/// InvalidInput, λ = λ⁰ (or zero) and the validation message.
std::optional<SolveResult> check_input(const LcpProblem& p, const Eigen::Ref<const Eigen::VectorXd>& lambda0,
                                       const std::string& solver, Eigen::VectorXd& lambda);

/// What a solver's provisional `Converged` stands for when it hands its result to finish:
/// the caller's stopping rule held (θ_k ≤ tolerance, or a residual ≤ options.tolerance [N]),
/// or the method's own claim of a solution (exact methods, iterating to solution_target).
enum class StopRule { Tolerance, Solution };

/// The one rule that decides every solver's status (docs/lcp.md "Statuses"). `provisional` is
/// what stopped the method (Converged = its stopping rule `rule` held). Returns Converged
/// exactly when the provisional status is Converged and `residual` (the natural residual at
/// the returned λ) is ≤ solution_target(p, o); a provisional Converged that fails the test
/// becomes ToleranceReached (rule Tolerance) or Failed (rule Solution); every other status
/// (SweepLimit: the budget ran out, whatever λ is worth) is kept.
SolveStatus decide_status(const LcpProblem& p, double residual, SolveStatus provisional, StopRule rule,
                          const SolverOptions& o);

/// Finishes a result whose r.status is provisional: guards against a non-finite λ, fills
/// residual (natural map) and sets r.status = decide_status(…); a demoted claim is explained
/// in r.message. Every solver ends here (or in refuse/InvalidInput paths, never Converged).
void finish(const LcpProblem& p, SolveResult& r, const SolverOptions& o, StopRule rule);
/// finish's last part for a result whose r.residual is already the natural residual of a
/// finite r.lambda: r.status = decide_status(…) and the message of a demoted claim.
void settle_status(const LcpProblem& p, SolveResult& r, const SolverOptions& o, StopRule rule);

/// The finished InvalidInput result of a matrix-free solver whose sweep could not be prepared
/// for this problem (`why`, from MatrixFreeSweep::prepare): λ unchanged, the message names the
/// solver and points at the assembled form, which handles every problem.
SolveResult refuse_matrix_free(const LcpProblem& p, Eigen::VectorXd lambda, const std::string& solver,
                               const std::string& why);

/// Row bounds in branch-free form: for row i with coupling row c_i,
///   lo_i = lo_fixed_i − μ_i·max(0, λ_{c_i}),   hi_i = hi_fixed_i + μ_i·max(0, λ_{c_i}).
/// Normal/standard rows have μ_i = 0 and c_i = i (the term vanishes, λ is finite);
/// friction rows have fixed parts 0 and c_i = normal_row[i], which reproduces ±μλ_n.
struct RowBounds {
  std::vector<double> lo_fixed, hi_fixed, mu;
  std::vector<int> coupled;
  explicit RowBounds(const LcpProblem& p);
};

/// Calls options.on_checkpoint(k, λ) for every k in options.checkpoints, once each, in
/// order; robust against unsorted, duplicate or non-positive entries (those are skipped).
/// A list that is already strictly increasing from k ≥ 1 (the bench's trace: every iteration,
/// thousands of them) is read in place: `options` outlives the cursor, and a copy per solve
/// and per part (prox-newton forwards them to each part it runs) cost as much as tens of sweeps
/// on a small problem.
class CheckpointCursor {
 public:
  explicit CheckpointCursor(const SolverOptions& o);
  CheckpointCursor(const CheckpointCursor&) = delete;  // ks_ may point into own_
  CheckpointCursor& operator=(const CheckpointCursor&) = delete;
  /// After sweep k.
  void after(int k, const Eigen::VectorXd& lambda);
  /// For methods whose iterates come k at a time (an outer iteration of several inner ones):
  /// the last checkpoint ≤ k not yet passed sees λ (the earlier ones are skipped).
  void reach(int k, const Eigen::VectorXd& lambda);
  /// A solver that stopped early at tolerance: the remaining checkpoints see the final λ
  /// (a larger budget would not have been used).
  void flush_final(const Eigen::VectorXd& lambda);

 private:
  [[nodiscard]] size_t size() const { return size_; }
  [[nodiscard]] int at(size_t i) const { return ks_[i]; }

  std::vector<int> own_;     // the sorted, unique, positive copy when the caller's list is not so
  const int* ks_ = nullptr;  // own_'s or the caller's entries
  size_t size_ = 0;
  size_t next_ = 0;
  const SolverOptions& o_;
};

/// The friction row's projection x = clamp(y, −t, t) with t = μ·max(0, λ_n) ≥ 0, and the
/// non-finite flag. With t = 0 (λ_n = 0: contact inactive) that is ±0 for every finite y, so
/// a predictable branch hands back 0 without waiting for y: the row leaves the dependency
/// chain of the sweep (pgs_matrix_free.cpp, "cost model"). A NaN y still sets `bad`.
inline double friction_clamp(double y, double t, bool& bad) {
  if (t > 0.0) {
    const double x = std::min(std::max(y, -t), t);
    bad |= !std::isfinite(x);
    return x;
  }
  bad |= !std::isfinite(y);
  return 0.0;
}

/// Rows whose diagonal A_ii is not > 0 (or whose 1/A_ii is not finite). The sweep kernels
/// never divide by them: such a row moves to the bound its residual points at, λ_i ← lo_i
/// if r_i > 0, λ_i ← hi_i if r_i < 0 (the limit of λ_i − r_i/A_ii for A_ii → 0⁺), and stays
/// where it is when that bound is infinite or r_i = 0.
inline double singular_row_update(double old, double r, double lo, double hi) {
  if (r > 0) return std::isfinite(lo) ? lo : old;
  if (r < 0) return std::isfinite(hi) ? hi : old;
  return old;
}

/// After the sweeps: if rows were singular and are not complementary at the returned λ
/// (natural residual of the row above 1e-12·max(1,‖b‖∞) and above the tolerance), the
/// status becomes Failed and the message names them; otherwise the message mentions them.
void report_singular_rows(const LcpProblem& p, const std::vector<int>& singular, SolveResult& r);

/// The bookkeeping of both sweep drivers after a finite sweep k with θ_k: records θ, calls the
/// checkpoints, and returns true (status set) when the tolerance is met or the iterates grow
/// without bound (θ_k > 1e12·max(θ_1, 1e-300)).
inline bool after_finite_sweep(int k, double theta, const Eigen::VectorXd& lambda, const SolverOptions& o,
                               CheckpointCursor& cp, double& theta1, SolveResult& res) {
  if (o.record_theta) res.theta.push_back(theta);
  if (k == 1) theta1 = theta;
  cp.after(k, lambda);
  if (o.tolerance > 0 && theta <= o.tolerance) {
    res.status = SolveStatus::Converged;
    cp.flush_final(lambda);
    return true;
  }
  if (theta > 1e12 * std::max(theta1, 1e-300) && k > 1) {
    res.status = SolveStatus::Diverged;
    res.message = "iterates grow without bound (theta grew from " + g_text(theta1) + " to " +
                  g_text(theta) + " by sweep " + std::to_string(k) + ")";
    return true;
  }
  return false;
}

/// A caller's look at a sweep method's iterate every `every` sweeps (run_sweeps): `stop(k, λ)`
/// after sweep k (k a multiple of `every`), with the iterate of that sweep; true ends the run
/// there (status SweepLimit before the shared rule). The method's own state (momentum, Δu)
/// carries on between looks, so a run judged this way makes the same sweeps as one without it up
/// to the sweep the hook stops it at.
struct SweepWatch {
  int every = 0;  ///< sweeps between looks (≤ 0: none)
  std::function<bool(int sweeps, const Eigen::VectorXd& lambda)> stop;
};

/// Generic driver of the sweep methods (PGS, PSOR, Jacobi). `sweep(λ, nonfinite)` performs
/// one sweep in place, returns θ_k = max_i |λ_i^k − λ_i^{k−1}| and sets nonfinite when an
/// update produced a non-finite value. The driver records θ, calls checkpoints, stops at
/// the tolerance, detects divergence (non-finite iterate → restore the previous sweep's λ;
/// θ_k > 1e12·max(θ_1, 1e-300) → iterates grow without bound) and fills the result. `watch`
/// (optional): the caller's look every watch->every sweeps, after the checkpoints.
template <class Sweep>
SolveResult run_sweeps(const LcpProblem& /*p*/, Eigen::VectorXd lambda, const SolverOptions& o,
                       Sweep&& sweep, const SweepWatch* watch = nullptr) {
  SolveResult res;
  res.status = SolveStatus::SweepLimit;
  const int max_sweeps = std::max(0, o.max_sweeps);
  if (o.record_theta) res.theta.reserve(static_cast<size_t>(std::min(max_sweeps, 1 << 20)));
  CheckpointCursor cp(o);
  Eigen::VectorXd last = lambda;
  double theta1 = 0.0;
  int done = 0;
  for (int k = 1; k <= max_sweeps; ++k) {
    last = lambda;  // n doubles per sweep: the price of returning the last finite iterate
    bool nonfinite = false;
    const double theta = sweep(lambda, nonfinite);
    if (nonfinite || !std::isfinite(theta)) {
      lambda = last;
      res.status = SolveStatus::Diverged;
      res.message = "iterate became non-finite in sweep " + std::to_string(k) +
                    "; returning the iterate of sweep " + std::to_string(k - 1);
      break;
    }
    done = k;
    if (after_finite_sweep(k, theta, lambda, o, cp, theta1, res)) break;
    if (watch != nullptr && watch->every > 0 && k % watch->every == 0 && watch->stop(k, lambda)) break;
  }
  res.sweeps = done;
  res.lambda = std::move(lambda);
  return res;
}

/// run_sweeps for kernels that read λ^{k−1} from one buffer and write λ^k to another:
/// `sweep(in, out, nonfinite)` returns θ_k. The buffers swap after every finite sweep, so
/// on a non-finite iterate the other buffer still holds the last finite one and no sweep
/// pays run_sweeps' copy of λ. `other` must have λ's size (its entries that the kernel never
/// writes must equal λ's). Same statuses, messages, checkpoints, θ and `watch` as run_sweeps.
/// `spare`, when set, receives the buffer that does not hold the result (its storage, for reuse).
template <class Sweep>
SolveResult run_sweeps_double_buffered(Eigen::VectorXd lambda, Eigen::VectorXd other, const SolverOptions& o,
                                       Sweep&& sweep, Eigen::VectorXd* spare = nullptr,
                                       const SweepWatch* watch = nullptr) {
  SolveResult res;
  res.status = SolveStatus::SweepLimit;
  const int max_sweeps = std::max(0, o.max_sweeps);
  if (o.record_theta) res.theta.reserve(static_cast<size_t>(std::min(max_sweeps, 1 << 20)));
  CheckpointCursor cp(o);
  double theta1 = 0.0;
  int done = 0;
  for (int k = 1; k <= max_sweeps; ++k) {
    bool nonfinite = false;
    const double theta = sweep(static_cast<const Eigen::VectorXd&>(lambda), other, nonfinite);
    if (nonfinite || !std::isfinite(theta)) {
      res.status = SolveStatus::Diverged;
      res.message = "iterate became non-finite in sweep " + std::to_string(k) +
                    "; returning the iterate of sweep " + std::to_string(k - 1);
      break;
    }
    lambda.swap(other);
    done = k;
    if (after_finite_sweep(k, theta, lambda, o, cp, theta1, res)) break;
    if (watch != nullptr && watch->every > 0 && k % watch->every == 0 && watch->stop(k, lambda)) break;
  }
  res.sweeps = done;
  res.lambda = std::move(lambda);
  if (spare != nullptr) spare->swap(other);
  return res;
}

}  // namespace dc::solvers
