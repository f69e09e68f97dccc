#include "solvers/prox_newton/cone/cone_passes.hpp"

#include <algorithm>
#include <cmath>

#include "solvers/prox_newton/cone/anderson.hpp"
#include "solvers/prox_newton/cone/shift_trust.hpp"

namespace dc::solvers::prox {

void de_saxce_shift(const LcpProblem& p, const Eigen::VectorXd& w, Eigen::VectorXd& shift) {
  shift.setZero(p.rows());
  for (int t = 0; t < p.rows(); ++t)
    if (p.is_friction_row(t)) shift[p.normal_row[static_cast<size_t>(t)]] = p.mu[t] * std::abs(w[t]);
}

namespace {

void add_work(const SubproblemOutcome& so, ConePassesOutcome& out) {
  out.newton += so.iterations;
  out.factorizations += so.factorizations;
  out.analyses += so.analyses;
  out.cg += so.cg_iterations;
  out.line_search_steps += so.line_search_steps;
}

/// δ (relative to max A_ii) after a pass at rel: kept unless `steer`, then shrunk after a solved
/// pass (down to min_shift, never back to failed_rel or below: with the trust region the δ of a
/// rejected following pass) and grown after an unsolved one.
double next_shift(const ConePassesDef& def, bool steer, bool converged, double rel, double failed_rel) {
  if (!steer) return rel;
  if (!converged) return std::max(rel, rel * def.shrink);
  const double next = std::max(def.min_shift, std::min(rel, rel / def.shrink));
  return next < rel && next <= failed_rel ? rel : next;
}

}  // namespace

ConePassesOutcome run_cone_passes(const LcpProblem& p, ConeNewton& cone, const Eigen::VectorXd& lambda0, double target,
                                  const ConePassesDef& def) {
  ConePassesOutcome out;
  Eigen::VectorXd lambda = lambda0;
  out.best = lambda;
  out.best_residual = natural_residual(p, lambda);
  const double start_residual = out.best_residual;
  const double diag = cone.max_diagonal();
  if (!(diag > 0)) return out;
  ConeSubproblem sub;
  double rel = def.shift;
  sub.delta = rel * diag;
  sub.stale_factor_iterations = def.stale_factor_iterations;
  bool following = def.follow_shift && def.follow_after == 0;
  Eigen::VectorXd w = lcp_velocity(p, lambda), shift, next_shift_vec;
  de_saxce_shift(p, w, shift);
  ShiftTrust trust(def.trust_radius, def.trust_grow, def.trust_retries, def.trust_fast);
  double failed_rel = 0;  // largest δ (relative) of a rejected following pass
  double failed_at = 0;   // the best hard residual then [N]
  int stalls = 0;
  Anderson acc(def.anderson);
  while (out.best_residual > target && out.passes < def.max_passes && out.newton < def.iterations) {
    ++out.passes;
    sub.follow_shift = following;
    if (following) {
      sub.c = p.b - sub.delta * lambda;
      trust.bound(shift, sub);
    } else {
      sub.c = p.b + shift - sub.delta * lambda;
    }
    sub.tolerance = def.inner_tolerance * std::max(target, out.best_residual);
    const int cap = following ? def.follow_iterations : def.inner_iterations;
    sub.max_iterations = std::min(cap, def.iterations - out.newton);
    Eigen::VectorXd next = lambda;
    const SubproblemOutcome so = cone.solve(sub, next);
    add_work(so, out);
    if (!next.allFinite()) break;
    const double res = natural_residual(p, next);
    if (def.on_pass) def.on_pass(out.passes, so, res);
    const double before = out.best_residual;
    if (res < out.best_residual) {
      out.best = next;
      out.best_residual = res;
      stalls = 0;
    } else if (++stalls >= def.max_stalls) {
      break;
    }
    const bool was_following = following;
    // With the trust region a following pass is accepted unless its hard residual rose above
    // trust_accept times the best (the proximal step on the exact problem makes progress even
    // where the hard residual rises for a pass, and an unsolved pass's iterate is still a step);
    // without it, only when solved with a lower hard residual than the best.
    const bool accepted = !was_following || (def.trust_radius > 0 ? res <= def.trust_accept * before
                                                                  : so.converged && res < before);
    if (def.follow_shift) {
      if (was_following)
        following = trust.after_following(accepted, res, before);
      else
        following = so.converged &&
                     (so.iterations <= def.follow_after || out.best_residual <= def.follow_below * start_residual);
    }
    if (!accepted) {
      ++out.rejected;
      next = out.best;  // a rejected following pass's iterate is no start
    }
    // With the shift following, δ shrinks after each solved following pass (and grows back
    // after a failed one); without it, after every solved pass.
    const bool steer = !def.follow_shift || was_following;
    if (was_following && !accepted && def.trust_radius > 0) {
      failed_rel = std::max(failed_rel, rel);
      failed_at = out.best_residual;
    }
    if (out.best_residual <= def.trust_forget * failed_at) failed_rel = 0;
    const double next_rel = next_shift(def, steer, so.converged, rel, failed_rel);
    if (def.anderson > 0) {
      // A blow-up or a new δ (another map): the history misleads.
      if (res > 10 * out.best_residual || next_rel != rel || was_following != following) acc.restart();
      Eigen::VectorXd mixed = acc.next(lambda, next);
      project_feasible(p, mixed);
      const double mres = natural_residual(p, mixed);
      if (std::isfinite(mres)) {
        if (mres < out.best_residual) {
          out.best = mixed;
          out.best_residual = mres;
        }
        next = std::move(mixed);
      }
    }
    lambda = std::move(next);
    w = lcp_velocity(p, lambda);
    de_saxce_shift(p, w, next_shift_vec);
    if (accepted) trust.moved((next_shift_vec - shift).lpNorm<Eigen::Infinity>());
    shift.swap(next_shift_vec);
    rel = next_rel;
    sub.delta = rel * diag;
  }
  return out;
}

}  // namespace dc::solvers::prox
