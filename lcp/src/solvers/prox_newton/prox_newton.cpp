// "prox-newton" (dc/lcp/prox_newton.hpp): the outer proximal/Tresca loop, the finish and the
// safeguard. Every stop test and the status go through status.hpp.
#include "dc/lcp/prox_newton.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "dc/core/error.hpp"
#include "dc/lcp/newton_sparse.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/lcp/proximal_point.hpp"
#include "solvers/prox_newton/guess_route.hpp"
#include "solvers/prox_newton/body_newton.hpp"
#include "solvers/prox_newton/checkpoint_work.hpp"
#include "solvers/prox_newton/cone/cone_passes.hpp"
#include "solvers/prox_newton/dual_newton.hpp"
#include "solvers/prox_newton/finish/mu_continuation.hpp"
#include "solvers/prox_newton/frozen_subproblem.hpp"
#include "solvers/prox_newton/lead/lead_rate.hpp"
#include "solvers/prox_newton/lead/lead_stage.hpp"
#include "solvers/prox_newton/newton_budget.hpp"
#include "solvers/prox_newton/options/def_check.hpp"
#include "solvers/prox_newton/passes.hpp"
#include "solvers/prox_newton/pivot_finish.hpp"
#include "solvers/prox_newton/status.hpp"
#include "solvers/exact/box_newton.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc {
namespace solvers::prox {

/// The machinery a solver object keeps across solves (factorisations and their analyses).
struct ProxParts {
  DualNewton dual;
  BodyNewton body;
  ConeNewton cone;
  NewtonSparseSolver finish;
  std::unique_ptr<LcpSolver> colored_lead;  // ProxLeadSweep::Colored's nncg-colored (made at its first use)
};

}  // namespace solvers::prox

struct ProxNewtonSolver::State {
  solvers::prox::ProxParts parts;
  ProxNewtonStats last;
  ProxNewtonStats at_checkpoint;  // checkpoint_stats()
};

namespace solvers::prox {
namespace {

/// x in %.3g form (residuals span many decades).
std::string sci(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

/// One solve: the outer loop over frozen subproblems, then finish and safeguard.
class ProxRun {
 public:
  ProxRun(const LcpProblem& p, const ProxNewtonDef& def, const SolverOptions& o, ProxParts& s,
          ProxNewtonStats& st, ProxNewtonStats& at_checkpoint, bool body, bool convex)
      : p_(p), def_(def), o_(o), s_(s), st_(st), body_(body), convex_(convex), target_(status_target(p, o)),
        work_(st, at_checkpoint), cp_options_(work_.watch(o)), cp_(cp_options_),
        budget_(def.newton_budget, def.newton_budget_gain) {}

  SolveResult run(Eigen::VectorXd lambda) {
    project_feasible(p_, lambda);
    best_ = lambda;
    best_res_ = hard_residual(p_, lambda);
    if (!std::isfinite(best_res_)) {
      best_ = lambda = Eigen::VectorXd::Zero(p_.rows());
      best_res_ = hard_residual(p_, lambda);
    }
    const Eigen::VectorXd guess = best_;
    // After a lead stage that lowered the hard residual at least lead_gain-fold but stopped
    // short of the target, a first Newton part runs from its best iterate. Otherwise, or when
    // that part misses the target too, the Newton part runs from the guess as without the
    // stage, with the best so far set aside as a candidate (a partly converged nncg iterate is
    // usually the better start, but can hold row modes the finish does not recover from).
    const double guess_res = best_res_;
    if (body_ && lead(guess) && by_ == Finisher::Lead && !reached(best_res_, target_)) {
      if (best_res_ * def_.lead_gain <= guess_res) {
        lambda = best_;
        budget_.begin(lead_fall_ >= def_.newton_budget_lead_fall, st_.factorizations);
        newton_part(lambda, false);
        budget_.end();
      }
      // A first Newton part out of its budget (newton_budget): nncg from the best iterate so
      // far, and the Newton part from the guess only when that missed the target too.
      if (budget_.spent() && !reached(best_res_, target_) && def_.safeguard_sweeps > 0) safeguard();
      if (!reached(best_res_, target_)) {
        const Eigen::VectorXd kept = best_;
        const double kept_res = best_res_;
        const Finisher kept_by = by_;
        best_ = lambda = guess;
        best_res_ = guess_res;
        by_ = Finisher::Guess;
        part_start_ = st_.newton + st_.finish_newton;
        from_guess_ = true;
        newton_part(lambda, true);
        if (kept_res < best_res_) {
          best_ = kept;
          best_res_ = kept_res;
          by_ = kept_by;
        }
      }
    } else {
      newton_part(lambda, true);
    }
    if (!reached(best_res_, target_) && def_.safeguard_sweeps > 0) safeguard();
    if (!reached(best_res_, target_) && def_.local_pivot_rows > 0) finish_by_local_pivoting();
    if (!reached(best_res_, target_) && best_res_ <= def_.continuation_within * target_ &&
        def_.continuation_stages > 0 && has_friction(p_)) {
      const ContinuationOutcome co = continuation_solve(p_, guess, def_, target_, std::max(0, o_.max_sweeps));
      st_.continuation_solves += co.solves;
      st_.factorizations += co.work.factorizations;
      st_.analyses += co.work.analyses;
      st_.pivots += co.work.pivots;
      consider(co.lambda, hard_residual(p_, co.lambda), Finisher::Continuation);
    }
    if (probe_best_res_ < best_res_) {
      best_ = probe_best_;
      best_res_ = probe_best_res_;
      by_ = Finisher::Prox;
    }
    SolveResult r;
    r.lambda = best_;
    r.sweeps = done();
    // Provisional status from the hard residual; the shared rule (solver_common) then decides.
    r.status = final_status(hard_residual(p_, r.lambda), target_, budget_left() <= 0);
    // The message first: finish appends the shared rule's explanation when it demotes a claim.
    r.message = work_message(by_, st_);
    const bool claimed = r.status == SolveStatus::Converged;
    finish(p_, r, o_, o_.tolerance > 0 ? StopRule::Tolerance : StopRule::Solution);
    if (r.status == SolveStatus::Converged) cp_.flush_final(r.lambda);
    if (!claimed && r.status != SolveStatus::Converged)
      r.message += "; residual " + sci(r.residual) + " N above target " + sci(target_) + " N";
    return r;
  }

 private:
  /// Newton iterations left of the current Newton part's budget (options.max_sweeps each).
  [[nodiscard]] int budget_left() const {
    return std::max(0, o_.max_sweeps) - (st_.newton + st_.finish_newton - part_start_);
  }
  /// Iterations so far, as the caller's checkpoints and SolveResult::sweeps count them: the lead
  /// stage's sweeps, then Newton iterations.
  [[nodiscard]] int done() const { return st_.lead_sweeps + st_.newton + st_.finish_newton; }
  /// The caller's checkpoints count the safeguard's sweeps too, in the order the parts ran.
  [[nodiscard]] int mark() const { return done() + st_.safeguard_sweeps; }

  /// Keeps λ when it beats the best hard residual; true when it did.
  bool consider(const Eigen::VectorXd& lambda, double res, Finisher by) {
    budget_.progress(res, st_.factorizations);
    if (!(res < best_res_)) return false;
    best_ = lambda;
    best_res_ = res;
    by_ = by;
    return true;
  }

  /// The body-space subproblem solver, bound to this problem at its first use: a solve that the
  /// lead stage finishes never needs Jᵀ, W and W⁻¹ (bind_body_metric).
  BodyNewton& body() {
    if (!body_bound_) {
      s_.body.bind(p_);
      body_bound_ = true;
    }
    return s_.body;
  }

  /// Body space with at least degenerate_rows rows per velocity unknown (ProxNewtonDef).
  [[nodiscard]] bool degenerate() const {
    return body_ && p_.rows() >= def_.degenerate_rows * static_cast<double>(p_.J.cols());
  }

  /// True once the first Newton part ran out of its budget (newton_budget.hpp).
  bool over_budget() { return budget_.over(st_.factorizations); }

  /// A run of passes from λ steered by `ps` (passes.hpp); λ ends at the last usable iterate.
  void outer(Eigen::VectorXd& lambda, const Passes& ps) {
    const double diag = body_ ? body().max_diagonal() : (p_.rows() > 0 ? p_.A.diagonal().maxCoeff() : 0.0);
    if (!(diag > 0)) return;
    double shift = ps.shift;
    const int newton0 = st_.newton;
    double failed_shift = 0;  // largest δ whose pass failed (steady_shift runs)
    int stalls = 0;
    std::vector<char> last_modes, finished_modes;
    FrozenSubproblem sub;
    for (int k = 0; k < def_.max_outer && !reached(best_res_, target_) && budget_left() > 0 &&
                    st_.newton - newton0 < ps.iterations && !over_budget();
         ++k) {
      ++st_.outer;
      freeze(p_, lambda, shift * diag, sub);
      sub.coupled = ps.coupled;
      sub.stale_factor_iterations = def_.stale_factor_iterations;
      // Inexact proximal point: the subproblem is solved to a fraction of the hard residual
      // (far away) and of the target (near the solution).
      sub.tolerance = def_.inner_tolerance * std::max(target_, best_res_);
      sub.max_iterations = std::min({ps.inner, budget_left(), ps.iterations - (st_.newton - newton0)});
      Eigen::VectorXd next = lambda;
      const SubproblemOutcome so = body_ ? body().solve(sub, next) : s_.dual.solve(sub, next);
      st_.newton += so.iterations;
      st_.factorizations += so.factorizations;
      st_.analyses += so.analyses;
      st_.line_search_steps += so.line_search_steps;
      st_.full_steps += so.full_steps;
      st_.krylov += so.krylov_iterations;
      st_.cg += so.cg_iterations;
      const double res = hard_residual(p_, next);
      const double before = best_res_;
      const bool improved = consider(next, res, Finisher::Prox);
      // In the dual form at min_shift the passes converge linearly: a slow one is a stall (the
      // proximal finish converges faster from the same iterate).
      const bool slow = (!body_ && shift <= def_.min_shift * (1 + 1e-9) && res > def_.pass_progress * before) ||
                        (ps.steady_shift && res > def_.pass_progress * before);
      const bool progressed = improved && !slow;
      // The proximal step is progress even when the hard residual rises for a pass; a failed
      // subproblem solve restarts from the best iterate with a larger δ.
      const bool usable = (so.converged || improved) && std::isfinite(res);
      lambda = usable ? next : best_;
      // δ follows the subproblem: a solved one allows a smaller δ (a longer proximal step), an
      // unsolved one asks for a larger (better conditioned) one. The hard residual is not
      // monotone along the proximal iteration, so it does not steer δ.
      shift = ps.steady_shift ? steady_shift(def_, shift, so.converged, res, before, failed_shift)
              : so.converged ? std::max(def_.min_shift, shift / def_.shrink)
                             : std::min(def_.max_shift, shift * def_.shrink);
      last_shift_ = shift;
      stalls = progressed ? 0 : stalls + 1;
      cp_.after(mark(), best_);
      if (reached(best_res_, target_) || stalls >= ps.max_stalls) break;
      std::vector<char> modes = hard_modes(p_, lambda);
      if (ps.finish && modes == last_modes && modes != finished_modes && def_.finish_iterations > 0) {
        finished_modes = modes;
        finish_with_newton_sparse(lambda, def_.finish_iterations);
      }
      last_modes = std::move(modes);
    }
  }

  /// The passes (or, without a convex subproblem, newton-sparse) from λ, then the finishes
  /// while the target is not reached. Not the `last` part: no pivoting, and the proximal finish
  /// gives up after a slow stretch (ProxNewtonDef::lead_finish_window), as the part after it
  /// starts afresh.
  void newton_part(Eigen::VectorXd& lambda, bool last) {
    if (convex_) {
      if (body_ && def_.exact_cone && s_.cone.bind(p_))
        cone_passes(lambda);
      else
        outer(lambda, frozen_passes(def_, body_, budget_left()));
      if (body_ && def_.body_finish && !reached(best_res_, target_) && !over_budget()) {
        lambda = best_;
        outer(lambda, coupled_passes(def_, budget_left()));
      }
    } else {
      finish_with_newton_sparse(lambda, budget_left());
    }
    if (!reached(best_res_, target_) && def_.proximal_finish && !over_budget())
      finish_by_proximal_point(!last);
    if (last && !reached(best_res_, target_) && def_.pivot_rows > 0 && !over_budget())
      finish_by_pivoting();
  }

  /// The lead stage (ProxNewtonDef::lead_sweeps; lead_stage.hpp): one nncg run from λ while
  /// LeadRate says it still converges (lead_window); its iterates go through consider().
  /// False when it did not run.
  bool lead(const Eigen::VectorXd& lambda) {
    const int cap = std::min(def_.lead_sweeps, std::max(0, o_.max_sweeps));
    if (cap <= 0 || reached(best_res_, target_)) return false;
    LeadStageDef ld;
    ld.cap = cap;
    const int bodies = static_cast<int>(p_.J.cols() / 3);
    ld.window = lead_window_chunks(def_.lead_window, def_.lead_window_bodies, bodies);
    const bool above = def_.lead_window_bodies > 0 && bodies > def_.lead_window_bodies;  // the window grew
    ld.gain = above ? def_.lead_window_gain_above : def_.lead_window_gain;
    const int stall = degenerate() && def_.degenerate_stall_chunks > 0 ? def_.degenerate_stall_chunks : def_.lead_stall_chunks;
    ld.stall = lead_window_chunks(stall, def_.lead_window_bodies, bodies);
    ld.start = best_res_;
    ld.target = target_;
    const bool colored = def_.lead_sweep == ProxLeadSweep::Colored ||
                         (def_.lead_sweep == ProxLeadSweep::Auto && p_.rows() >= def_.lead_colored_rows);
    if (colored) {
      if (!s_.colored_lead) s_.colored_lead = make_nncg_colored();
      ld.colored = s_.colored_lead.get();
    }
    if (degenerate() && def_.probe_sweeps > 0 && def_.probe_iterations > 0)
      ld.probe = [this](int sweeps) { return probe(sweeps); };
    if (degenerate()) {
      ld.drift_jumps = def_.degenerate_drift_jumps;
      ld.drift_linearity = def_.degenerate_drift_linearity;
    }
    SolverOptions so;
    forward_checkpoints(so, InFlightPart::lead());
    st_.lead_sweeps = run_lead_stage(p_, lambda, ld, std::move(so), [this](const Eigen::VectorXd& x) {
      consider(x, hard_residual(p_, x), Finisher::Lead);
      return best_res_;
    }, &lead_fall_, &st_.drift_jumps);
    return true;
  }

  /// A probe at the lead stage's look after `sweeps` sweeps (ProxNewtonDef::probe_sweeps): the
  /// coupled passes from the best iterate; true when they reached the target. Their Newton
  /// iterations follow the lead's sweeps so far in the caller's checkpoint count, and the lead's
  /// later sweeps follow them (probe_newton_).
  bool probe(int sweeps) {
    if (probes_ >= def_.probe_count || sweeps < def_.probe_sweeps || reached(best_res_, target_) || budget_left() <= 0)
      return false;
    if (def_.probe_reach > 0 && best_res_ > def_.probe_reach * target_) return false;  // a later look
    // A later probe only after nncg's best fell probe_refall-fold since the last one's start.
    if (probes_ > 0 && best_res_ * def_.probe_refall > probed_at_) return false;
    ++probes_;
    probed_at_ = best_res_;
    st_.lead_sweeps = sweeps;  // mark() counts the lead's sweeps so far
    const int newton0 = st_.newton;
    // What the lead stage and the parts after it see stays as without the probe (a probe's
    // iterate that missed the target is a worse start for them on box piles, and would count
    // as progress in the lead's window rule and the Newton budget); the probe's best is a
    // candidate for the answer (run's end).
    const Eigen::VectorXd kept = best_;
    const double kept_res = best_res_;
    const Finisher kept_by = by_;
    const NewtonBudget kept_budget = budget_;
    Eigen::VectorXd lambda = best_;
    outer(lambda, probe_passes(def_, budget_left()));
    probe_newton_ += st_.newton - newton0;
    if (!reached(best_res_, target_)) {
      if (best_res_ < kept_res && best_res_ < probe_best_res_) {
        probe_best_ = best_;
        probe_best_res_ = best_res_;
      }
      best_ = kept;
      best_res_ = kept_res;
      by_ = kept_by;
      budget_ = kept_budget;
    }
    // The passes after the lead stage start as without the probe: no kept factor of the
    // coupled H to precondition their first direction with.
    body().forget_factor();
    st_.lead_sweeps = 0;  // the lead's checkpoints add their own sweeps (CheckpointWork)
    return reached(best_res_, target_);
  }

  /// The exact-cone passes (cone_passes.hpp) from λ; λ becomes the best iterate. None when an
  /// earlier stage (the lead) already reached the target: run_cone_passes tests only its own start.
  void cone_passes(Eigen::VectorXd& lambda) {
    if (reached(best_res_, target_)) return;
    ConePassesDef cd;
    cd.shift = def_.cone_shift;
    cd.max_passes = def_.max_outer;
    cd.inner_iterations = def_.cone_inner_iterations;
    cd.inner_tolerance = def_.cone_inner_tolerance;
    cd.stale_factor_iterations = def_.stale_factor_iterations;
    cd.max_stalls = def_.cone_max_stalls;
    cd.anderson = def_.cone_anderson;
    cd.follow_shift = def_.cone_follow_shift;
    cd.follow_after = def_.cone_follow_after;
    cd.follow_iterations = def_.cone_follow_iterations;
    cd.follow_below = def_.cone_follow_below;
    cd.trust_radius = def_.cone_trust_radius;
    cd.trust_grow = def_.cone_trust_grow;
    cd.trust_retries = def_.cone_trust_retries;
    cd.trust_forget = def_.cone_trust_forget;
    cd.trust_accept = def_.cone_trust_accept;
    cd.shrink = def_.cone_shrink;
    cd.min_shift = std::min(def_.cone_min_shift, def_.cone_shift);
    cd.iterations = budget_left();
    const ConePassesOutcome co = run_cone_passes(p_, s_.cone, lambda, target_, cd);
    st_.outer += co.passes;
    st_.newton += co.newton;
    st_.factorizations += co.factorizations;
    st_.analyses += co.analyses;
    st_.cg += co.cg;
    st_.line_search_steps += co.line_search_steps;
    consider(co.best, co.best_residual, Finisher::Prox);
    lambda = best_;
    cp_.after(mark(), best_);
  }

  /// At most `iterations` newton-sparse iterations on the hard problem from λ, within the Newton
  /// part's budget unless `own_count`.
  void finish_with_newton_sparse(Eigen::VectorXd& lambda, int iterations, bool own_count = false) {
    if (!assembled_) assembled_ = &with_assembled_matrix(p_, local_);
    SolverOptions fo;
    fo.max_sweeps = own_count ? iterations : std::min(iterations, budget_left());
    fo.tolerance = target_;
    fo.record_theta = false;
    if (fo.max_sweeps <= 0) return;
    forward_checkpoints(fo, InFlightPart::newton_sparse(s_.finish));
    const SolveResult r = s_.finish.solve(*assembled_, lambda, fo);
    const NewtonSparseStats fs = s_.finish.last_stats();
    st_.finish_newton += fs.iterations;
    st_.factorizations += fs.factorizations;
    st_.analyses += fs.analyses;
    const double res = hard_residual(p_, r.lambda);
    if (consider(r.lambda, res, Finisher::NewtonSparse)) lambda = r.lambda;
  }

  /// The proximal-point route (newton-sparse on the hard problem shifted by δI around λ_k) from
  /// the best iterate: hard-Coulomb Newton steps that stay well posed on a singular A.
  void finish_by_proximal_point(bool windowed) {
    if (!assembled_) assembled_ = &with_assembled_matrix(p_, local_);
    const int budget = budget_left();
    if (budget <= 0) return;
    ProximalPointDef pd = body_ ? def_.finish_route : def_.dual_finish_route;
    if (windowed && def_.lead_finish_window > 0) {
      pd.progress_window = def_.lead_finish_window;
      pd.window_stops = true;
    }
    if (windowed && def_.lead_fallback_doublings >= 0) pd.newton_sparse.fallback_doublings = def_.lead_fallback_doublings;
    if (windowed && def_.lead_fallback_cap_fall > 0) pd.newton_sparse.fallback_cap_fall = def_.lead_fallback_cap_fall;
    if (windowed && def_.lead_newton_stalls > 0) pd.newton_sparse.max_stalls = def_.lead_newton_stalls;
    if (windowed && def_.lead_initial_shift > 0) pd.initial_shift = def_.lead_initial_shift;
    if (degenerate() && def_.degenerate_fallback_momentum) pd.newton_sparse.fallback_momentum = true;
    if (from_guess_) apply_guess_route(def_, lead_route_floor_, pd);
    pd.inner_iterations = std::min(pd.inner_iterations, budget);
    if (budget_.on()) {
      const int base = st_.factorizations;
      pd.stop_after = [this, base](int factorizations, double best) {
        budget_.progress(best, base + factorizations);
        return budget_.over(base + factorizations);
      };
    }
    SolverOptions fo;
    fo.tolerance = target_;
    fo.record_theta = false;
    fo.exact_tolerance = o_.exact_tolerance;
    ProximalPointStats ps;
    forward_checkpoints(fo, InFlightPart::proximal_point(ps));
    const SolveResult r = solve_proximal_point(*assembled_, best_, fo, pd, &ps);
    st_.factorizations += ps.factorizations;
    st_.finish_newton += r.sweeps;
    st_.proximal_finish_newton += r.sweeps;
    if (windowed) lead_route_floor_ = ps.floor;
    if (r.lambda.size() == p_.rows() && r.lambda.allFinite())
      consider(r.lambda, hard_residual(p_, r.lambda), Finisher::ProximalPoint);
  }

  /// Lemke's pivoting on the split LCP (pivot_finish.hpp) when it is small enough, then the
  /// newton-sparse finish from its answer (round-off of the tableau) for the iterations left.
  void finish_by_pivoting() {
    if (!assembled_) assembled_ = &with_assembled_matrix(p_, local_);
    const int size = pivot_lcp_size(*assembled_);
    if (size < 0 || size > def_.pivot_rows) return;
    const PivotOutcome po = pivot_solve(*assembled_);
    st_.pivots += po.pivots;
    if (!po.lambda) return;
    Eigen::VectorXd lambda = *po.lambda;
    consider(lambda, hard_residual(p_, lambda), Finisher::Pivot);
    // Newton from Lemke's point even when the tableau's round-off left it worse than the best
    // iterate: its row modes are the ones that matter.
    if (!reached(best_res_, target_)) {
      constexpr int kPolishIterations = 30;  // quadratic from the right modes; more only wanders
      const double before = best_res_;
      finish_with_newton_sparse(lambda, kPolishIterations);
      if (best_res_ < before) by_ = Finisher::Pivot;
    }
  }

  /// The local pivoting finish (ProxNewtonDef::local_pivot_rows): rounds of Lemke on the
  /// violators' neighbourhood with the rest fixed at the best iterate, each followed by the
  /// newton-sparse polish from Lemke's point (its own iteration count: the Newton parts' budget
  /// may be spent; nncg once more from there did not lower the residual on the impact steps
  /// measured, so none runs). A round that does not lower the best hard residual ends the finish.
  void finish_by_local_pivoting() {
    if (!assembled_) assembled_ = &with_assembled_matrix(p_, local_);
    constexpr int kPolishIterations = 30;  // as finish_by_pivoting
    for (int round = 0; round < def_.local_pivot_rounds && !reached(best_res_, target_); ++round) {
      const std::vector<int> rows = local_pivot_rows(*assembled_, best_, def_.local_pivot_threshold * best_res_,
                                                     def_.local_pivot_rings, def_.local_pivot_rows);
      if (rows.empty()) return;
      const PivotOutcome po = local_pivot_solve(*assembled_, best_, rows, def_.local_pivot_shift);
      st_.pivots += po.pivots;
      if (!po.lambda) return;
      const double before = best_res_;
      Eigen::VectorXd lambda = *po.lambda;
      consider(lambda, hard_residual(p_, lambda), Finisher::Pivot);
      if (!reached(best_res_, target_)) {
        const double lemke = best_res_;
        finish_with_newton_sparse(lambda, kPolishIterations, true);
        if (best_res_ < lemke) by_ = Finisher::Pivot;
      }
      if (!(best_res_ < before)) return;
    }
  }

  /// The caller's checkpoints still ahead, numbered from the iterations done so far, for a
  /// finish's own iteration count: its iterate at each reaches the caller through cp_.
  /// `part` says what the finish's iterations are and where its factorisations so far are read
  /// (checkpoint_work.hpp).
  void forward_checkpoints(SolverOptions& fo, const InFlightPart& part) {
    if (!o_.on_checkpoint) return;
    const int base = mark();
    fo.checkpoints.reserve(o_.checkpoints.size());
    for (const int k : o_.checkpoints)
      if (k > base) fo.checkpoints.push_back(k - base);
    fo.on_checkpoint = [this, base, part](int it, const Eigen::VectorXd& lambda) {
      work_.begin(part, it);
      cp_.after(base + it + (part.kind == InFlightPart::Kind::Lead ? probe_newton_ : 0), lambda);
      work_.end();
    };
  }

  /// nncg from the best iterate in chunks until the target or safeguard_sweeps.
  void safeguard() {
    const auto nncg = make_nncg();
    SolverOptions so;
    so.record_theta = false;
    so.tolerance = 0.0;
    Eigen::VectorXd lambda = best_;
    constexpr int kChunk = 100;
    while (st_.safeguard_sweeps < def_.safeguard_sweeps && !reached(best_res_, target_)) {
      so.max_sweeps = std::min(kChunk, def_.safeguard_sweeps - st_.safeguard_sweeps);
      so.checkpoints.clear();
      forward_checkpoints(so, InFlightPart::safeguard());
      const SolveResult r = nncg->solve(p_, lambda, so);
      st_.safeguard_sweeps += std::max(r.sweeps, 1);
      if (!r.lambda.allFinite()) break;
      lambda = r.lambda;
      consider(lambda, hard_residual(p_, lambda), Finisher::Nncg);
      if (r.status != SolveStatus::SweepLimit && r.status != SolveStatus::Converged) break;
    }
  }

  const LcpProblem& p_;
  const ProxNewtonDef& def_;
  const SolverOptions& o_;
  ProxParts& s_;
  ProxNewtonStats& st_;
  bool body_, convex_;
  double target_;
  CheckpointWork work_;
  SolverOptions cp_options_;  // o_ with on_checkpoint through work_ (checkpoint_stats)
  CheckpointCursor cp_;
  Eigen::VectorXd best_;
  double best_res_ = INFINITY;
  double last_shift_ = 0;  // δ after the last pass, relative to max A_ii
  int part_start_ = 0;     // Newton iterations before the current Newton part
  double lead_route_floor_ = 0.0;  // δ's failure floor the windowed proximal finish ended with
  bool from_guess_ = false;        // in the Newton part from the guess after the first part
  double lead_fall_ = 1.0;         // the lead stage's LeadRate::window_fall()
  int probes_ = 0;                 // the lead stage's probes so far
  double probed_at_ = INFINITY;    // best hard residual where the last probe started [N]
  bool body_bound_ = false;        // s_.body bound to p_ (body())
  Eigen::VectorXd probe_best_;     // the probe's best iterate when it missed the target
  double probe_best_res_ = INFINITY;
  int probe_newton_ = 0;           // Newton iterations of the probe during the lead stage
  NewtonBudget budget_;            // the first Newton part's (newton_budget)
  Finisher by_ = Finisher::Guess;
  std::optional<LcpProblem> local_;
  const LcpProblem* assembled_ = nullptr;
};

}  // namespace
}  // namespace solvers::prox

ProxNewtonSolver::ProxNewtonSolver(const ProxNewtonDef& def) : def_(def), state_(std::make_unique<State>()) {
  solvers::prox::check_def(def_);
}

ProxNewtonSolver::~ProxNewtonSolver() = default;

ProxNewtonStats ProxNewtonSolver::last_stats() const { return state_->last; }

ProxNewtonStats ProxNewtonSolver::checkpoint_stats() const { return state_->at_checkpoint; }

SolveResult ProxNewtonSolver::solve(const LcpProblem& problem, const Eigen::VectorXd& lambda0, const SolverOptions& o) {
  ProxNewtonStats st;
  state_->at_checkpoint = {};
  Eigen::VectorXd lambda;
  const bool body = def_.body_space && problem.has_jacobian() && problem.inv_mass.size() == problem.J.cols();
  std::optional<LcpProblem> local;
  const LcpProblem* p = &problem;
  if (!body) p = &solvers::with_assembled_matrix(problem, local);
  if (auto bad = solvers::check_input(*p, lambda0, name(), lambda)) {
    state_->last = st;
    return *bad;
  }
  // The dual form needs a symmetric A (a QP); a non-symmetric A (a general LCP from a file) has
  // no convex subproblem, and newton-sparse alone takes the whole budget.
  bool convex = body;
  if (!body) {
    if (!p->A.isCompressed()) {  // the factor's pattern key reads the compressed arrays
      if (!local) local.emplace(*p);
      local->A.makeCompressed();
      p = &*local;
    }
    convex = solvers::is_symmetric(p->A);
    if (convex) state_->parts.dual.bind(p->A);
  }
  solvers::prox::ProxRun run(*p, def_, o, state_->parts, st, state_->at_checkpoint, body, convex);
  SolveResult r = run.run(std::move(lambda));
  state_->last = st;
  return r;
}

std::unique_ptr<LcpSolver> make_prox_newton(const ProxNewtonDef& def) { return std::make_unique<ProxNewtonSolver>(def); }

}  // namespace dc
