#include "dc/bench/bench_runner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>

#include "dc/bench/bench_merge.hpp"
#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/warmstart/oracle.hpp"
#include "solver_comparison.hpp"

namespace dc::bench {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// The trade at one budget: the residual of λ_B, its error against λ*, and the penetration
/// and energy after a step with λ_B (against `e_star`, the energy after a step with λ*).
void record_trade(World& world, const LcpProblem& p, const Eigen::VectorXd& lam, const Eigen::VectorXd& oracle,
                  double e_star, StarterRecord& rec, StepOutcome& outcome) {
  rec.residual.push_back(natural_residual(p, lam));
  rec.lambda_error.push_back((lam - oracle).cwiseAbs().maxCoeff());
  world.predict(lam, outcome);
  rec.penetration.push_back(outcome.max_penetration());
  rec.energy_error.push_back(outcome.energy() - e_star);
}

/// Budgets the solver did not reach (it stopped early, e.g. diverged) get the final iterate's
/// trade, then the last value repeated, so every step has one entry per budget.
void pad_unreached_budgets(World& world, const LcpProblem& p, const SolveResult& fr, const Eigen::VectorXd& oracle,
                           double e_star, std::size_t trade_before, std::size_t budgets, StarterRecord& rec,
                           StepOutcome& outcome) {
  while (rec.residual.size() - trade_before < budgets) {
    const std::size_t last = rec.residual.size() - 1;
    if (rec.residual.size() == trade_before) {
      record_trade(world, p, fr.lambda, oracle, e_star, rec, outcome);
    } else {
      rec.residual.push_back(rec.residual[last]);
      rec.lambda_error.push_back(rec.lambda_error[last]);
      rec.penetration.push_back(rec.penetration[last]);
      rec.energy_error.push_back(rec.energy_error[last]);
    }
  }
}

/// First k (1-based) with θ_k ≤ tol; −1 if none.
int sweeps_to_tolerance(const std::vector<double>& theta, double tolerance) {
  for (std::size_t k = 0; k < theta.size(); ++k)
    if (theta[k] <= tolerance) return static_cast<int>(k) + 1;
  return -1;
}

/// Sweeps to tol with the higher cap: a step that did not reach tol within o.sweeps
/// continues from the convergence run's last iterate (PGS only carries λ between sweeps).
int sweeps_to_tolerance_high(LcpSolver& solver, const LcpProblem& p, const SolveResult& fr, int to_tol,
                             const BenchOptions& o) {
  if (to_tol >= 0) return to_tol;
  SolverOptions more;
  more.max_sweeps = o.max_sweeps - o.sweeps;
  more.tolerance = o.tolerance;
  more.record_theta = false;
  const SolveResult mr = solver.solve(p, fr.lambda, more);
  return stopped_at_tolerance(mr.status) ? o.sweeps + mr.sweeps : -1;  // θ ≤ tol, solution or not
}

/// Everything one starter does on one step: guess, fixed-sweep run with checkpoints, timed
/// tolerance-mode run. `oracle` is this step's λ* (for errors; shared with oracle starters
/// in paired mode). Returns the fixed-sweep solution (rollout integrates with it); `guess`, when
/// given, receives λ⁰ (the solver comparison starts every solver from it).
Eigen::VectorXd evaluate_starter(World& world, WarmStarter& ws, const Eigen::VectorXd& oracle,
                                 bool share_oracle, LcpSolver& solver, const BenchOptions& o,
                                 const std::vector<int>& budgets, StarterRecord& rec,
                                 StepOutcome& outcome, Eigen::VectorXd* guess = nullptr) {
  const LcpProblem& p = world.problem();
  const StepView view{world, share_oracle ? &oracle : nullptr};
  rec.seed.push_back(world.def().bodies.seed);
  rec.step.push_back(world.step_index());
  rec.rows.push_back(p.rows());

  auto t0 = Clock::now();
  Eigen::VectorXd lambda0 = ws.initial_guess(view);
  const double guess_ms = ms_since(t0);
  if (lambda0.size() != p.rows())
    throw InvalidArgument("warm starter '" + ws.name() + "' returned " + std::to_string(lambda0.size()) +
                          " values for a problem with " + std::to_string(p.rows()) + " rows");
  if (!lambda0.allFinite())
    throw InvalidArgument("warm starter '" + ws.name() + "' returned a non-finite guess");
  rec.oracle_ms.push_back(ws.oracle_ms());
  rec.warmstart_ms.push_back(std::max(0.0, guess_ms - ws.oracle_ms()));
  rec.initial_error.push_back(p.rows() ? (lambda0 - oracle).cwiseAbs().maxCoeff() : 0.0);

  // Reference energy after a step with λ*, for the energy error of each budget.
  world.predict(oracle, outcome);
  const double e_star = outcome.energy();

  // 1. Convergence run: fixed sweeps, θ recorded, trade sampled at the budgets (the
  //    sampling's time is not the solver's).
  SolverOptions fixed;
  fixed.max_sweeps = o.sweeps;
  fixed.tolerance = 0.0;
  fixed.record_theta = true;
  fixed.checkpoints = budgets;
  double callback_ms = 0;
  fixed.on_checkpoint = [&](int, const Eigen::VectorXd& lam) {
    const auto c0 = Clock::now();
    record_trade(world, p, lam, oracle, e_star, rec, outcome);
    callback_ms += ms_since(c0);
  };
  const std::size_t trade_before = rec.residual.size();
  t0 = Clock::now();
  SolveResult fr = solver.solve(p, lambda0, fixed);
  const double fixed_ms = ms_since(t0) - callback_ms;
  if (fr.status == SolveStatus::InvalidInput) throw InvalidArgument("bench: solver rejected the problem: " + fr.message);
  pad_unreached_budgets(world, p, fr, oracle, e_star, trade_before, budgets.size(), rec, outcome);
  rec.sweep_ns_per_row.push_back(fr.sweeps > 0 && p.rows() > 0 ? 1e6 * fixed_ms / fr.sweeps / p.rows() : 0.0);
  const int to_tol = sweeps_to_tolerance(fr.theta, o.tolerance);
  rec.sweeps_to_tol.push_back(to_tol);
  if (o.max_sweeps > o.sweeps) rec.sweeps_to_tol_high.push_back(sweeps_to_tolerance_high(solver, p, fr, to_tol, o));
  std::vector<float> theta_row(static_cast<std::size_t>(o.sweeps), 0.0f);  // 0 after an early stop
  for (std::size_t k = 0; k < theta_row.size() && k < fr.theta.size(); ++k) theta_row[k] = static_cast<float>(fr.theta[k]);
  rec.theta.append(theta_row);  // to disk now: θ is most of the results (theta_rows.hpp)

  // 2. Timed run: what a simulator would actually do (stop at θ ≤ tol).
  SolverOptions timed;
  timed.max_sweeps = o.sweeps;
  timed.tolerance = o.tolerance;
  timed.record_theta = false;
  t0 = Clock::now();
  const SolveResult tr = solver.solve(p, lambda0, timed);
  rec.solve_ms.push_back(ms_since(t0));
  (void)tr;

  ws.observe(view, fr.lambda);
  if (guess) *guess = std::move(lambda0);
  return fr.lambda;
}

/// The reference λ of a step without the tight oracle: builtin + PGS to tol / 100.
OracleSolution cheap_reference(const World& w, const LcpProblem& p, LcpSolver& solver, const BenchOptions& o) {
  const auto builtin = default_warm_starters().make("builtin");  // stateless: cheap to make per step
  const Eigen::VectorXd guess = builtin->initial_guess(StepView{w, nullptr});
  SolverOptions so;
  so.max_sweeps = std::max(o.sweeps, o.max_sweeps);
  so.tolerance = o.tolerance / 100;
  so.record_theta = false;
  SolveResult r = solver.solve(p, guess, so);
  OracleSolution out;
  out.lambda = std::move(r.lambda);
  out.residual = natural_residual(p, out.lambda);
  return out;
}

/// Warm-up: advance `w` by o.warmup_steps with builtin + PGS until tol (nothing recorded).
void warm_up(World& w, LcpSolver& solver, const BenchOptions& o) {
  const auto builtin = default_warm_starters().make("builtin");
  SolverOptions so;
  so.max_sweeps = o.sweeps;
  so.tolerance = o.tolerance;
  so.record_theta = false;
  for (int s = 0; s < o.warmup_steps; ++s) {
    w.collide();
    w.assemble();
    const LcpProblem& p = solver.needs_assembled_matrix() ? w.ensure_assembled_matrix() : w.problem();
    if (p.rows() == 0) {
      w.integrate(Eigen::VectorXd());
      continue;
    }
    w.integrate(solver.solve(p, builtin->initial_guess(StepView{w, nullptr}), so).lambda);
  }
}

/// A step's collide and assemble stages, timed (the stages every starter shares), and its
/// LCP — with the assembled A when the solver reads it, which then counts as assembly.
struct AssembledStep {
  const LcpProblem* problem = nullptr;
  double collide_ms = 0, assemble_ms = 0;
};

AssembledStep collide_and_assemble(World& w, LcpSolver& solver) {
  AssembledStep out;
  auto ts = Clock::now();
  w.collide();
  out.collide_ms = ms_since(ts);
  ts = Clock::now();
  w.assemble();
  out.problem = solver.needs_assembled_matrix() ? &w.ensure_assembled_matrix() : &w.problem();
  out.assemble_ms = ms_since(ts);
  return out;
}

/// The checks of the options that need nothing resolved, before the wall clock starts.
void check_options(const BenchOptions& o) {
  if (o.warmstarts.empty()) throw ConfigError("bench: no warm starters selected");
  if (o.seeds.empty()) throw ConfigError("bench: no scene seeds selected");
  if (o.sweeps < 1) throw ConfigError("bench: --sweeps must be >= 1");
  if (o.jobs < 1) throw ConfigError("bench: --jobs must be >= 1");
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance)) throw ConfigError("bench: --tol must be a finite number > 0");
  o.scene.validate();
}

/// Empty results for `o` with the budgets resolved: the fixed budget (0 = min(100, sweeps))
/// joins the trade's budgets (o.budgets or the log-spaced default), sorted and unique.
BenchResults results_with_budgets(const BenchOptions& o) {
  BenchResults r;
  r.options = o;
  r.budgets = o.budgets.empty() ? default_budgets(o.sweeps) : o.budgets;
  r.options.budget = o.budget > 0 ? o.budget : std::min(100, o.sweeps);
  if (r.options.budget > o.sweeps) throw ConfigError("bench: --budget must lie in 1..sweeps");
  if (o.max_sweeps != 0 && o.max_sweeps <= o.sweeps) throw ConfigError("bench: --max-sweeps must exceed --sweeps");
  if (o.warmup_steps < 0) throw ConfigError("bench: --warmup-steps must be >= 0");
  r.budgets.push_back(r.options.budget);
  std::sort(r.budgets.begin(), r.budgets.end());
  r.budgets.erase(std::unique(r.budgets.begin(), r.budgets.end()), r.budgets.end());
  if (r.budgets.front() < 1 || r.budgets.back() > o.sweeps)
    throw ConfigError("bench: budgets must lie in 1..sweeps");
  return r;
}

using Starters = std::vector<std::unique_ptr<WarmStarter>>;

/// One run_bench call: the solver, the results being filled, and the progress count. Both
/// modes append seed by seed, in the order of o.seeds (mpi_bench.hpp relies on it).
class BenchRun {
 public:
  /// `make_mutex` (may be null) serialises the registry's factories when several runs share
  /// it from different threads: a starter may read a model file while it is made.
  /// `scratch` holds the θ rows (shared by the runs of one bench, which may be on different threads).
  BenchRun(const BenchOptions& o, const WarmStarterRegistry& registry, const ProgressFn& progress, BenchResults& r,
           std::shared_ptr<ScratchFile> scratch, std::mutex* make_mutex = nullptr)
      : o_(o), registry_(registry), progress_(progress), r_(r), solver_(make_solver(o.solver)),
        scratch_(std::move(scratch)), make_mutex_(make_mutex) {}

  /// Makes every starter once before the long run, so that an unknown name, or an oracle
  /// starter in a run without the oracle, fails at once; adds their records to the results.
  void add_starter_records() {
    for (const auto& name : o_.warmstarts) {
      auto ws = make_starter(name, o_.env);
      StarterRecord rec;
      rec.theta = ThetaRows(scratch_);
      rec.name = ws->name();
      rec.uses_oracle = ws->uses_oracle();
      if (rec.uses_oracle && !o_.oracle)
        throw ConfigError("bench: warm starter '" + rec.name + "' needs the oracle, which this run skips (--no-oracle)");
      r_.starters.push_back(std::move(rec));
    }
    comparison_ = std::make_unique<SolverComparison>(o_, r_);
    total_ = static_cast<long>(o_.seeds.size()) * std::max(0, o_.scene.time.steps - o_.warmup_steps) *
             (o_.mode == Mode::Paired ? 1 : static_cast<long>(o_.warmstarts.size()));
  }

  /// Every step of the scene with this seed, in the run's mode.
  void run_seed(std::uint64_t seed) {
    WorldDef def = o_.scene;
    def.bodies.seed = seed;
    // Fresh starters per seed, their random streams from the seed alone, so a seed's results
    // do not depend on which seeds ran before it.
    WarmStartEnv env = o_.env;
    env.seed = o_.env.seed ^ (seed * 0x9e3779b97f4a7c15ULL);
    Starters starters;
    for (const auto& name : o_.warmstarts) starters.push_back(make_starter(name, env));
    if (o_.mode == Mode::Paired) {
      run_paired(seed, def, starters);
    } else {
      for (std::size_t i = 0; i < starters.size(); ++i) run_rollout(seed, def, i, *starters[i]);
    }
  }

 private:
  std::unique_ptr<WarmStarter> make_starter(const std::string& name, const WarmStartEnv& env) const {
    if (!make_mutex_) return registry_.make(name, env);
    const std::lock_guard<std::mutex> lock(*make_mutex_);
    return registry_.make(name, env);
  }

  /// Paired mode: one reference trajectory advanced with λ*; every starter solves each of
  /// its steps. The first seed's trajectory is recorded for the report's frame.
  void run_paired(std::uint64_t seed, const WorldDef& def, const Starters& starters) {
    World ref(def);
    warm_up(ref, *solver_, o_);
    const bool record = seed == o_.seeds.front();  // the report shows a frame of it
    if (record) {
      r_.reference = std::make_shared<TrajectoryRecorder>(ref);
      r_.reference_scene = scene_to_toml(def);
    }
    const auto oracle_starter = default_warm_starters().make("builtin");
    for (int s = o_.warmup_steps; s < o_.scene.time.steps; ++s) {
      paired_step(ref, seed, s, record, *oracle_starter, starters);
      report_progress("seed " + std::to_string(seed) + " step " + std::to_string(s + 1));
    }
  }

  void paired_step(World& ref, std::uint64_t seed, int s, bool record, WarmStarter& oracle_starter,
                   const Starters& starters) {
    const AssembledStep step = collide_and_assemble(ref, *solver_);
    const LcpProblem& p = *step.problem;
    if (p.rows() == 0) {
      ++r_.skipped_steps;
      ref.integrate(Eigen::VectorXd());
      if (record) {
        StepReport nothing;  // no contacts: nothing to solve
        nothing.solve.status = SolveStatus::Converged;
        r_.reference->record_step(ref, nothing);
      }
      return;
    }
    r_.collide_ms.push_back(step.collide_ms);
    r_.assemble_ms.push_back(step.assemble_ms);
    // One shared oracle per step, started from the previous step's λ* matched by key
    // (cheaper; the oracle's cost is reported apart and never enters a total).
    auto t0 = Clock::now();
    const Eigen::VectorXd oracle_guess = oracle_starter.initial_guess(StepView{ref, nullptr});
    const OracleSolution os = o_.oracle ? solve_oracle(p, &oracle_guess) : cheap_reference(ref, p, *solver_, o_);
    r_.oracle_ms.push_back(ms_since(t0));
    r_.oracle_residual.push_back(os.residual);
    r_.step_seed.push_back(seed);
    r_.step_index.push_back(s);
    r_.step_rows.push_back(p.rows());
    Eigen::VectorXd guess;
    for (std::size_t i = 0; i < starters.size(); ++i) {
      evaluate_starter(ref, *starters[i], os.lambda, true, *solver_, o_, r_.budgets, r_.starters[i], outcome_, &guess);
      if (!o_.solvers.empty())
        comparison_->run(p, ref.def().world.gravity, i, seed, guess, r_.starters[i].warmstart_ms.back());
    }
    t0 = Clock::now();
    ref.integrate(os.lambda);
    r_.integrate_ms.push_back(ms_since(t0));
    if (record) {
      StepReport rep;
      rep.contacts = static_cast<int>(ref.contacts().size());
      rep.rows = p.rows();
      rep.solve.status = os.accurate ? SolveStatus::Converged : SolveStatus::SweepLimit;
      rep.solve.residual = os.residual;
      r_.reference->record_step(ref, rep);
    }
  }

  /// Rollout mode: starter i drives its own world with its fixed-sweep λ. The shared-stage
  /// timings and the step list are those of the first starter's world.
  void run_rollout(std::uint64_t seed, const WorldDef& def, std::size_t i, WarmStarter& ws) {
    World w(def);
    warm_up(w, *solver_, o_);
    for (int s = o_.warmup_steps; s < o_.scene.time.steps; ++s) {
      rollout_step(w, seed, s, i, ws);
      report_progress(r_.starters[i].name + " seed " + std::to_string(seed));
    }
  }

  void rollout_step(World& w, std::uint64_t seed, int s, std::size_t i, WarmStarter& ws) {
    const AssembledStep step = collide_and_assemble(w, *solver_);
    const LcpProblem& p = *step.problem;
    if (p.rows() == 0) {
      if (i == 0) ++r_.skipped_steps;
      w.integrate(Eigen::VectorXd());
      return;
    }
    const OracleSolution os = o_.oracle ? solve_oracle(p) : cheap_reference(w, p, *solver_, o_);
    if (i == 0) {
      r_.step_seed.push_back(seed);
      r_.step_index.push_back(s);
    }
    // In rollout mode each starter computes its own oracle (reported as its cost).
    const Eigen::VectorXd lam = evaluate_starter(w, ws, os.lambda, false, *solver_, o_, r_.budgets, r_.starters[i], outcome_);
    const auto ts = Clock::now();
    w.integrate(lam);
    if (i == 0) {
      r_.collide_ms.push_back(step.collide_ms);
      r_.assemble_ms.push_back(step.assemble_ms);
      r_.integrate_ms.push_back(ms_since(ts));
    }
  }

  void report_progress(const std::string& note) {
    ++done_;
    if (progress_) progress_(done_, total_, note);
  }

  const BenchOptions& o_;
  const WarmStarterRegistry& registry_;
  const ProgressFn& progress_;
  BenchResults& r_;
  const std::unique_ptr<LcpSolver> solver_;
  std::unique_ptr<SolverComparison> comparison_;  // runs only when o.solvers is not empty
  StepOutcome outcome_;  // reused by every evaluation
  std::shared_ptr<ScratchFile> scratch_;
  std::mutex* make_mutex_;
  long done_ = 0, total_ = 0;
};

/// o.jobs threads take the seeds one at a time (the next seed in o.seeds order goes to the first
/// free thread); each seed runs into its own results with its own solver and starters, and the
/// results are joined in o.seeds order. Every figure but the timings is therefore that of one
/// thread; the timings share the machine (docs/bench.md "Parallel seeds").
BenchResults run_seeds_in_parallel(const BenchOptions& o, const WarmStarterRegistry& registry,
                                   const ProgressFn& progress, const std::shared_ptr<ScratchFile>& scratch) {
  const std::size_t n = o.seeds.size();
  std::vector<BenchResults> per_seed;
  per_seed.reserve(n);
  for (std::size_t i = 0; i < n; ++i) per_seed.push_back(results_with_budgets(o));
  std::mutex make_mutex, progress_mutex;
  long done = 0;
  // Every run holds all the seeds in its options (so that the first seed's run records the
  // report's frame), so its progress total is already the whole bench's.
  const ProgressFn one_step = [&](long, long total, const std::string& note) {
    const std::lock_guard<std::mutex> lock(progress_mutex);
    ++done;
    if (progress) progress(done, total, note);
  };
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < n;) {
      try {
        BenchRun run(o, registry, one_step, per_seed[i], scratch, &make_mutex);
        run.add_starter_records();
        run.run_seed(o.seeds[i]);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next.store(n);  // the other threads stop after their current seed
      }
    }
  };
  std::vector<std::thread> threads;
  const std::size_t count = std::min<std::size_t>(static_cast<std::size_t>(o.jobs), n);
  for (std::size_t t = 0; t < count; ++t) threads.emplace_back(worker);
  for (auto& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
  BenchResults r = std::move(per_seed[0]);
  for (std::size_t i = 1; i < n; ++i) {
    append_results(r, per_seed[i]);  // the θ rows stay in the shared file: only offsets move
    per_seed[i] = BenchResults{};    // freed as we go: the joined records never coexist with all the parts
  }
  return r;
}

}  // namespace

std::vector<int> default_budgets(int sweeps) {
  std::vector<int> out;
  for (long decade = 1; decade <= sweeps; decade *= 10)
    for (int m : {10, 15, 20, 30, 50, 70})
      if (const long b = decade * m / 10; b <= sweeps && (out.empty() || b > out.back())) out.push_back(static_cast<int>(b));
  if (out.empty() || out.back() != sweeps) out.push_back(sweeps);
  return out;
}

BenchResults run_bench(const BenchOptions& o, const WarmStarterRegistry& registry, const ProgressFn& progress) {
  check_options(o);
  const auto wall0 = Clock::now();
  BenchResults r;
  // One nameless temporary file for every starter's θ rows, from every thread (theta_rows.hpp).
  const auto scratch = std::make_shared<ScratchFile>(o.scratch_dir);
  if (o.jobs > 1 && o.seeds.size() > 1) {
    r = run_seeds_in_parallel(o, registry, progress, scratch);
  } else {
    r = results_with_budgets(o);
    BenchRun run(o, registry, progress, r, scratch);
    run.add_starter_records();
    for (const std::uint64_t seed : o.seeds) run.run_seed(seed);
  }
  r.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  return r;
}

}  // namespace dc::bench
