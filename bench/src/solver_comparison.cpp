#include "solver_comparison.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "dc/core/error.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/prox_newton.hpp"

namespace dc::bench {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Where the accuracy trace of one solve got to.
struct Trace {
  int reached = -1;         // first iteration with accuracy ≤ R (−1: never)
  double reached_ms = 0.0;  // solve time until then [ms]
  double last = 0.0;        // accuracy of the last traced point
};

/// The work of `solver`'s last solve: (numeric factorisations, outer passes), −1 where it does
/// not count them.
std::pair<int, int> last_work(const LcpSolver& solver) {
  if (const auto* ns = dynamic_cast<const NewtonSparseSolver*>(&solver))
    return {ns->last_stats().factorizations, -1};
  if (const auto* pn = dynamic_cast<const ProxNewtonSolver*>(&solver)) {
    const ProxNewtonStats st = pn->last_stats();
    return {st.factorizations, st.outer};
  }
  return {-1, -1};
}

/// Numeric factorisations of `solver`'s solve so far, read from an on_checkpoint callback (−1
/// where it does not count them).
int factorizations_so_far(const LcpSolver& solver) {
  if (const auto* ns = dynamic_cast<const NewtonSparseSolver*>(&solver)) return ns->last_stats().factorizations;
  if (const auto* pn = dynamic_cast<const ProxNewtonSolver*>(&solver)) return pn->checkpoint_stats().factorizations;
  return -1;
}

/// Newton iterations up to iteration `it` of `solver`'s last solve (its iterations as checkpoints
/// count them; −1 where it does not count work): prox-newton's less its lead stage's nncg sweeps,
/// which come first.
int newton_iterations_to(const LcpSolver& solver, int it) {
  if (dynamic_cast<const NewtonSparseSolver*>(&solver) != nullptr) return it;
  if (const auto* pn = dynamic_cast<const ProxNewtonSolver*>(&solver))
    return std::max(0, it - pn->last_stats().lead_sweeps);
  return -1;
}

/// True for the solvers last_work reads.
bool counts_work(const LcpSolver& solver) {
  return dynamic_cast<const NewtonSparseSolver*>(&solver) != nullptr ||
         dynamic_cast<const ProxNewtonSolver*>(&solver) != nullptr;
}

}  // namespace

double weight_scale(const LcpProblem& p, Vec2 gravity) {
  const double g = std::sqrt(gravity.x * gravity.x + gravity.y * gravity.y);
  double heaviest = 0.0;
  for (int k = 0; k + 1 < p.inv_mass.size(); k += 3)
    if (p.inv_mass[k] > 0) heaviest = std::max(heaviest, 1.0 / p.inv_mass[k]);
  const double w = heaviest * g;
  return w > 0 && std::isfinite(w) ? w : 1.0;
}

std::vector<int> accuracy_checkpoints(int cap) {
  std::vector<int> out;
  for (int k = 1; k <= cap; k = k < 20 ? k + 1 : std::max(k + 1, static_cast<int>(std::ceil(k * 1.03))))
    out.push_back(k);
  if (!out.empty() && out.back() != cap) out.push_back(cap);
  return out;
}

SolverComparison::SolverComparison(const BenchOptions& o, BenchResults& r) : o_(o), r_(r) {
  if (o.solvers.empty()) return;
  if (o.mode != Mode::Paired) throw ConfigError("bench: --solvers needs paired mode (identical LCPs for every pair)");
  if (!(o.accuracy > 0) || !std::isfinite(o.accuracy)) throw ConfigError("bench: --accuracy must be a finite number > 0");
  for (const SolverId& solver : o.solvers) {
    for (const StarterRecord& starter : r.starters) {
      trace_.push_back(make_solver(solver));
      timed_.push_back(make_solver(solver));
      SolverPairRecord pair;
      pair.solver = trace_.back()->name();
      pair.starter = starter.name;
      r.pairs.push_back(std::move(pair));
    }
  }
}

void SolverComparison::run(const LcpProblem& p, Vec2 gravity, std::size_t starter, std::uint64_t seed,
                           const Eigen::VectorXd& lambda0, double warmstart_ms) {
  const double scale = weight_scale(p, gravity);
  const int cap = o_.max_sweeps > 0 ? o_.max_sweeps : o_.sweeps;
  const double initial = natural_residual(p, lambda0) / scale;
  for (std::size_t s = 0; s < o_.solvers.size(); ++s) {
    const std::size_t k = s * r_.starters.size() + starter;
    SolverPairRecord& rec = r_.pairs[k];
    rec.seed.push_back(seed);
    rec.weight_scale.push_back(scale);
    rec.trace_ms.push_back(warmstart_ms);
    rec.trace_accuracy.push_back(initial);
    // 1. The trace: checkpoints until accuracy ≤ R (their evaluation is not the solver's time).
    //    The solver stops at its own tolerance R·scale/100 (θ for sweep methods, the residual
    //    for newton-sparse) or the cap; after R is reached the checkpoints return at once.
    Trace tr;
    tr.last = initial;
    double run_ms = 0.0;
    std::pair<int, int> work{-1, -1};
    std::pair<int, int> to_r{-1, -1};  // (factorisations, Newton iterations) to the first checkpoint at R
    int fac_at_r = -1;                 // factorisations at the first checkpoint at R
    if (initial <= o_.accuracy) {
      tr.reached = 0;
      if (counts_work(*trace_[k])) {
        work = {0, dynamic_cast<const ProxNewtonSolver*>(trace_[k].get()) ? 0 : -1};
        to_r = {0, 0};
      }
    } else {
      SolverOptions so;
      so.max_sweeps = cap;
      so.tolerance = o_.accuracy * scale / 100;
      so.record_theta = false;
      so.checkpoints = accuracy_checkpoints(cap);
      double callback_ms = 0.0;
      Clock::time_point t0;
      Eigen::VectorXd seen;  // the last traced λ: the checkpoints after a solver stopped all see its final λ
      so.on_checkpoint = [&](int it, const Eigen::VectorXd& lam) {
        if (tr.reached >= 0) return;
        const auto c0 = Clock::now();
        if (seen.size() == lam.size() && seen == lam) {
          callback_ms += ms_since(c0);
          return;
        }
        seen = lam;
        const double t = std::chrono::duration<double, std::milli>(c0 - t0).count() - callback_ms;
        tr.last = natural_residual(p, lam) / scale;
        rec.trace_ms.push_back(warmstart_ms + t);
        rec.trace_accuracy.push_back(tr.last);
        if (tr.last <= o_.accuracy) {
          tr.reached = it;
          tr.reached_ms = t;
          fac_at_r = factorizations_so_far(*trace_[k]);
        }
        callback_ms += ms_since(c0);
      };
      t0 = Clock::now();
      const SolveResult res = trace_[k]->solve(p, lambda0, so);
      run_ms = ms_since(t0) - callback_ms;
      if (res.status == SolveStatus::InvalidInput)
        throw InvalidArgument("bench: solver '" + rec.solver + "' rejected the problem: " + res.message);
      work = last_work(*trace_[k]);
      // Checkpoints after the solver stopped see its final λ: they count at its own iterations.
      if (tr.reached > res.sweeps) tr.reached = res.sweeps;
      if (tr.reached < 0 && res.residual / scale <= o_.accuracy) {  // stopped between checkpoints
        tr.reached = res.sweeps;
        tr.reached_ms = run_ms;
        tr.last = res.residual / scale;
        rec.trace_ms.push_back(warmstart_ms + run_ms);
        rec.trace_accuracy.push_back(tr.last);
      }
      // The work to the checkpoint at R; R between checkpoints, or never: the whole solve's.
      if (counts_work(*trace_[k]))
        to_r = {fac_at_r >= 0 ? fac_at_r : work.first,
                newton_iterations_to(*trace_[k], tr.reached >= 0 ? tr.reached : res.sweeps)};
    }
    rec.iterations_to_accuracy.push_back(tr.reached);
    rec.ms_to_accuracy.push_back(warmstart_ms + (tr.reached >= 0 ? tr.reached_ms : run_ms));
    rec.final_accuracy.push_back(tr.last);
    rec.factorizations.push_back(work.first);
    rec.outer_passes.push_back(work.second);
    rec.factorizations_to_accuracy.push_back(to_r.first);
    rec.newton_to_accuracy.push_back(to_r.second);
    rec.trace_offsets.push_back(rec.trace_ms.size());
    // 2. The timed solve to the run's θ tolerance (the starters' total column, for this solver),
    //    with the comparison's cap.
    SolverOptions to;
    to.max_sweeps = cap;
    to.tolerance = o_.tolerance;
    to.record_theta = false;
    const auto t1 = Clock::now();
    const SolveResult tres = timed_[k]->solve(p, lambda0, to);
    rec.total_ms.push_back(warmstart_ms + ms_since(t1));
    (void)tres;
  }
}

}  // namespace dc::bench
