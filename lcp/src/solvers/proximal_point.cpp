// The proximal-point route around an exact solver (dc/lcp/proximal_point.hpp).
#include "dc/lcp/proximal_point.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "solvers/solver_common.hpp"

namespace dc {

namespace {

void check_def(const ProximalPointDef& d) {
  const auto positive = [](double x) { return std::isfinite(x) && x > 0; };
  if (!positive(d.initial_shift) || !positive(d.min_shift) || !positive(d.max_shift) || d.min_shift > d.max_shift)
    throw InvalidArgument("proximal point: shifts must be finite, > 0, min_shift <= max_shift");
  if (!(std::isfinite(d.shrink) && d.shrink > 1)) throw InvalidArgument("proximal point: shrink must be > 1");
  if (d.max_outer < 1 || d.inner_iterations < 1)
    throw InvalidArgument("proximal point: max_outer and inner_iterations must be >= 1");
  if (d.max_stalls < 0 || d.floor_stalls < 0)
    throw InvalidArgument("proximal point: max_stalls and floor_stalls must be >= 0");
  if (!(std::isfinite(d.initial_floor) && d.initial_floor >= 0))
    throw InvalidArgument("proximal point: initial_floor must be finite and >= 0");
  if (!(std::isfinite(d.floor_decay) && d.floor_decay >= 1))
    throw InvalidArgument("proximal point: floor_decay must be finite and >= 1");
  if (d.progress_window < 0) throw InvalidArgument("proximal point: progress_window must be >= 0");
  if (!(d.progress_factor > 0 && d.progress_factor <= 1))
    throw InvalidArgument("proximal point: progress_factor must be in (0, 1]");
  if (!(std::isfinite(d.inner_forcing) && d.inner_forcing >= 0 && d.inner_forcing < 1))
    throw InvalidArgument("proximal point: inner_forcing must be in [0, 1)");
}

/// The shifted problem A + δ I with A alone (no J: lcp_velocity would otherwise evaluate the
/// unshifted J M⁻¹ Jᵀ Δt matrix-free) and the contact structure kept for the solvers.
LcpProblem shifted(const LcpProblem& p, double delta) {
  LcpProblem s;
  SparseRowMatrix I(p.rows(), p.rows());
  I.setIdentity();
  s.A = p.A + delta * I;
  s.b = p.b;
  s.lo = p.lo;
  s.hi = p.hi;
  s.normal_row = p.normal_row;
  s.mu = p.mu;
  return s;
}

/// The progress_window stop: the best residual after each outer iteration, the outer
/// iteration the window counts from, and whether it released the failure floor.
struct ProgressWindow {
  std::vector<double> best_after;
  int start = 0;
  bool released = false;
  /// Whether the best residual `best` [N] before outer iteration k fell less than
  /// progress_factor-fold over the last progress_window outer iterations.
  bool slow(const ProximalPointDef& d, int k, double best) const {
    const int w = d.progress_window;
    return w > 0 && k - start >= w && best > d.progress_factor * best_after[static_cast<std::size_t>(k - w)];
  }
  /// After slow() at outer iteration k: true to stop the route. Else, slow at a raised failure
  /// floor with release_floor, δ falls again from here (once when window_stops, else each
  /// time; a failed inner solve raises the floor again), and the window restarts.
  bool stops(const ProximalPointDef& d, int k, double& floor, double& shift) {
    const bool release = d.release_floor && floor > d.min_shift && (!released || !d.window_stops);
    if (!release && d.window_stops) return true;
    if (release) {
      released = true;
      floor = d.min_shift;
      shift = std::max(floor, shift / d.shrink);
    }
    start = k;
    return false;
  }
};

std::string stop_message(const ProximalPointDef& d, bool slowed, int stalls, int floor_stalls) {
  if (d.floor_stalls > 0 && floor_stalls >= d.floor_stalls)
    return "proximal point: stalled: " + std::to_string(floor_stalls) +
           " outer iterations at the raised shift floor without a new best residual";
  if (slowed)
    return "proximal point: best residual fell less than progress_factor over " +
           std::to_string(d.progress_window) + " outer iterations";
  if (d.max_stalls > 0 && stalls >= d.max_stalls)
    return "proximal point: " + std::to_string(stalls) + " outer iterations without a new best residual";
  return "proximal point: outer iteration limit reached";
}

}  // namespace

SolveResult solve_proximal_point(const LcpProblem& problem, const Eigen::VectorXd& lambda0,
                                 const SolverOptions& options, const ProximalPointDef& def,
                                 ProximalPointStats* stats) {
  if (stats) *stats = {};
  check_def(def);
  std::optional<LcpProblem> local;
  const LcpProblem& p = solvers::with_assembled_matrix(problem, local);
  Eigen::VectorXd lambda;
  if (auto bad = solvers::check_input(p, lambda0, "proximal point", lambda)) return *bad;
  const double target = options.tolerance > 0 ? options.tolerance : solution_target(p, options);
  // stop_at_target: the first inner iterate at the original problem's target ends the route.
  Eigen::VectorXd at_target;
  double at_target_residual = 0.0;
  NewtonSparseDef inner_def = def.newton_sparse;
  if (def.stop_at_target)
    inner_def.stop_when = [&p, &at_target, &at_target_residual, target](int, const Eigen::VectorXd& x) {
      const double res = natural_residual(p, x);
      if (!(res <= target)) return false;
      at_target = x;
      at_target_residual = res;
      return true;
    };
  const auto inner = def.inner_solver.kind == SolverKind::NewtonSparse ? make_newton_sparse(inner_def)
                                                                        : make_solver(def.inner_solver);
  const double diag = p.rows() > 0 ? p.A.diagonal().cwiseAbs().maxCoeff() : 0.0;
  SolverOptions inner_options;
  inner_options.max_sweeps = def.inner_iterations;
  inner_options.record_theta = false;
  inner_options.exact_tolerance = options.exact_tolerance;
  // A caller's target below the solution target binds the inner solves too: an inner solve
  // that stops above it returns its start unchanged and the outer loop cannot progress.
  if (options.tolerance > 0) inner_options.tolerance = std::min(target, solution_target(p, options));
  const double inner_target = inner_options.tolerance > 0 ? inner_options.tolerance : solution_target(p, options);

  // Checkpoints after each outer iteration, at the inner iterations so far (CheckpointCursor::reach).
  solvers::CheckpointCursor cp(options);
  SolveResult out;  // λ and residual: the best iterate
  out.lambda = lambda;
  out.residual = natural_residual(p, lambda);
  Eigen::VectorXd centre = lambda;  // λ_k
  double floor = std::clamp(def.initial_floor, def.min_shift, def.max_shift);  // raised above every failed shift
  double shift = std::max(def.initial_shift, floor);
  int stalls = 0;                // consecutive outer iterations without a new best
  int floor_stalls = 0;          // of those, consecutive ones at a raised floor (floor_stalls)
  ProgressWindow window;
  bool slowed = false;    // stopped by progress_window
  bool asked = false;     // stopped by stop_after
  int factorizations = 0;  // the inner solves' numeric factorisations (stop_after)
  for (int k = 0; k < def.max_outer && out.residual > target && diag > 0 &&
                  (def.max_stalls == 0 || stalls < def.max_stalls) &&
                  (def.floor_stalls == 0 || floor_stalls < def.floor_stalls);
       ++k) {
    if (window.slow(def, k, out.residual) && window.stops(def, k, floor, shift)) {
      slowed = true;
      break;
    }
    const double delta = shift * diag;
    LcpProblem sub = shifted(p, delta);
    sub.b = p.b - delta * centre;
    // Inexact inner solve (ProximalPointDef::inner_forcing): a looser stop while far away.
    const double loose = def.inner_forcing * out.residual;
    inner_options.tolerance = loose > inner_target ? loose : (options.tolerance > 0 ? inner_target : 0.0);
    const SolveResult r = inner->solve(sub, centre, inner_options);
    out.sweeps += r.sweeps;
    if (const auto* ns = dynamic_cast<const NewtonSparseSolver*>(inner.get())) {
      factorizations += ns->last_stats().factorizations;
      if (stats) {
        stats->factorizations += ns->last_stats().factorizations;
        stats->krylov_iterations += ns->last_stats().krylov_iterations;
      }
    }
    if (at_target.size() == p.rows()) {
      out.lambda = at_target;
      out.residual = at_target_residual;
      cp.reach(out.sweeps, out.lambda);
      break;
    }
    if (r.status == SolveStatus::InvalidInput) {
      // The inner solver refuses this kind of problem (lemke on friction rows): every shifted
      // problem has the same rows, so say so instead of running out the outer iterations.
      out.status = SolveStatus::InvalidInput;
      out.message = "proximal point: " + r.message;
      out.lambda = lambda;
      solvers::finish(p, out, options, solvers::StopRule::Solution);
      return out;
    }
    const double residual = natural_residual(p, r.lambda);
    ++stalls;
    floor_stalls = shift <= floor && floor > def.min_shift ? floor_stalls + 1 : 0;
    if (residual < out.residual) {
      out.lambda = r.lambda;
      out.residual = residual;
      stalls = 0;
      floor_stalls = 0;
    }
    cp.reach(out.sweeps, out.lambda);
    if (def.stop_after && def.stop_after(factorizations, out.residual)) {
      asked = true;
      break;
    }
    if (def.progress_window > 0) window.best_after.push_back(out.residual);
    if (r.status == SolveStatus::Converged || (loose > inner_target && stopped_at_tolerance(r.status))) {
      // The proximal step is the method's progress even when it raises the residual of the
      // original problem for a while (that residual is not monotone along the iteration).
      centre = r.lambda;
      floor = std::max(def.min_shift, floor / def.floor_decay);
      shift = std::max(floor, shift / def.shrink);
    } else {
      // Too small a shift for this problem: never go back to it (shrinking again would only
      // oscillate between a failed and a converged shift and lose the progress in between).
      centre = out.lambda;
      shift = std::min(def.max_shift, shift * def.shrink);
      floor = std::max(floor, shift);
    }
  }
  if (stats) stats->floor = floor;
  out.status = out.residual <= target ? SolveStatus::Converged : SolveStatus::SweepLimit;
  if (out.status == SolveStatus::Converged) cp.flush_final(out.lambda);
  if (out.status != SolveStatus::Converged)
    out.message = asked ? "proximal point: stopped by the caller's budget" : stop_message(def, slowed, stalls, floor_stalls);
  // A target the caller gave (options.tolerance [N]) is a stopping rule, not the solution test.
  solvers::finish(p, out, options, options.tolerance > 0 ? solvers::StopRule::Tolerance : solvers::StopRule::Solution);
  return out;
}

}  // namespace dc
