#include "solvers/prox_newton/cone/cone_passes.hpp"

#include <algorithm>
#include <cmath>

#include "solvers/prox_newton/cone/anderson.hpp"

namespace dc::solvers::prox {

void de_saxce_shift(const LcpProblem& p, const Eigen::VectorXd& w, Eigen::VectorXd& shift) {
  shift.setZero(p.rows());
  for (int t = 0; t < p.rows(); ++t)
    if (p.is_friction_row(t)) shift[p.normal_row[static_cast<size_t>(t)]] = p.mu[t] * std::abs(w[t]);
}

ConePassesOutcome run_cone_passes(const LcpProblem& p, ConeNewton& cone, const Eigen::VectorXd& lambda0, double target,
                                  const ConePassesDef& def) {
  ConePassesOutcome out;
  Eigen::VectorXd lambda = lambda0;
  out.best = lambda;
  out.best_residual = natural_residual(p, lambda);
  const double diag = cone.max_diagonal();
  if (!(diag > 0)) return out;
  ConeSubproblem sub;
  double rel = def.shift;
  sub.delta = rel * diag;
  sub.stale_factor_iterations = def.stale_factor_iterations;
  bool following = def.follow_shift && def.follow_after == 0;
  Eigen::VectorXd w = lcp_velocity(p, lambda), shift;
  int stalls = 0;
  Anderson acc(def.anderson);
  while (out.best_residual > target && out.passes < def.max_passes && out.newton < def.iterations) {
    ++out.passes;
    sub.follow_shift = following;
    if (following) {
      sub.c = p.b - sub.delta * lambda;
    } else {
      de_saxce_shift(p, w, shift);
      sub.c = p.b + shift - sub.delta * lambda;
    }
    sub.tolerance = def.inner_tolerance * std::max(target, out.best_residual);
    const int cap = following ? def.follow_iterations : def.inner_iterations;
    sub.max_iterations = std::min(cap, def.iterations - out.newton);
    Eigen::VectorXd next = lambda;
    const SubproblemOutcome so = cone.solve(sub, next);
    out.newton += so.iterations;
    out.factorizations += so.factorizations;
    out.analyses += so.analyses;
    out.cg += so.cg_iterations;
    out.line_search_steps += so.line_search_steps;
    if (!next.allFinite()) break;
    const double res = natural_residual(p, next);
    if (def.on_pass) def.on_pass(out.passes, so, res);
    if (res < out.best_residual) {
      out.best = next;
      out.best_residual = res;
      stalls = 0;
    } else if (++stalls >= def.max_stalls) {
      break;
    }
    const bool was_following = following;
    if (def.follow_shift)
      following = following ? so.converged && res <= out.best_residual
                            : so.converged && so.iterations <= def.follow_after;
    if (was_following && !following) next = out.best;  // the failed following pass's iterate is no start
    // With the shift following, δ shrinks after each solved following pass (and grows back
    // after a failed one); without it, after every solved pass.
    const bool steer = !def.follow_shift || was_following;
    const double next_shift = !steer       ? rel
                              : so.converged ? std::max(def.min_shift, std::min(rel, rel / def.shrink))
                                             : std::max(rel, rel * def.shrink);
    if (def.anderson > 0) {
      // A blow-up or a new δ (another map): the history misleads.
      if (res > 10 * out.best_residual || next_shift != rel || was_following != following) acc.restart();
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
    rel = next_shift;
    sub.delta = rel * diag;
  }
  return out;
}

}  // namespace dc::solvers::prox
