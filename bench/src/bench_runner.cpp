#include "dc/bench/bench_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/bench/bench_statistics.hpp"

namespace dc::bench {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Everything one starter does on one step: guess, fixed-sweep run with checkpoints, timed
/// tolerance-mode run. `oracle` is this step's λ* (for errors; shared with oracle starters
/// in paired mode). Returns the fixed-sweep solution (rollout integrates with it).
Eigen::VectorXd evaluate_starter(World& world, WarmStarter& ws, const Eigen::VectorXd& oracle,
                                 bool share_oracle, const LcpSolver& solver, const BenchOptions& o,
                                 const std::vector<int>& budgets, StarterRecord& rec,
                                 StepOutcome& outcome) {
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

  // 1. Convergence run: fixed sweeps, θ recorded, trade sampled at the budgets.
  SolverOptions fixed;
  fixed.max_sweeps = o.sweeps;
  fixed.tolerance = 0.0;
  fixed.record_theta = true;
  fixed.checkpoints = budgets;
  double callback_ms = 0;
  fixed.on_checkpoint = [&](int, const Eigen::VectorXd& lam) {
    const auto c0 = Clock::now();
    rec.residual.push_back(natural_residual(p, lam));
    rec.lambda_error.push_back((lam - oracle).cwiseAbs().maxCoeff());
    world.predict(lam, outcome);
    rec.penetration.push_back(outcome.max_penetration());
    rec.energy_error.push_back(outcome.energy() - e_star);
    callback_ms += ms_since(c0);
  };
  const std::size_t trade_before = rec.residual.size();
  t0 = Clock::now();
  SolveResult fr = solver.solve(p, lambda0, fixed);
  const double fixed_ms = ms_since(t0) - callback_ms;
  if (fr.status == SolveStatus::InvalidInput) throw InvalidArgument("bench: solver rejected the problem: " + fr.message);
  // Budgets the solver did not reach (it stopped early, e.g. diverged): repeat the last value.
  while (rec.residual.size() - trade_before < budgets.size()) {
    const std::size_t last = rec.residual.size() - 1;
    if (rec.residual.size() == trade_before) {
      rec.residual.push_back(natural_residual(p, fr.lambda));
      rec.lambda_error.push_back((fr.lambda - oracle).cwiseAbs().maxCoeff());
      world.predict(fr.lambda, outcome);
      rec.penetration.push_back(outcome.max_penetration());
      rec.energy_error.push_back(outcome.energy() - e_star);
    } else {
      rec.residual.push_back(rec.residual[last]);
      rec.lambda_error.push_back(rec.lambda_error[last]);
      rec.penetration.push_back(rec.penetration[last]);
      rec.energy_error.push_back(rec.energy_error[last]);
    }
  }
  rec.sweep_ns_per_row.push_back(fr.sweeps > 0 && p.rows() > 0 ? 1e6 * fixed_ms / fr.sweeps / p.rows() : 0.0);
  int to_tol = -1;
  for (std::size_t k = 0; k < fr.theta.size(); ++k)
    if (fr.theta[k] <= o.tolerance) { to_tol = static_cast<int>(k) + 1; break; }
  rec.sweeps_to_tol.push_back(to_tol);
  if (o.max_sweeps > o.sweeps) {
    // Higher cap: continue from the last iterate (PGS only carries λ between sweeps).
    int high = to_tol;
    if (to_tol < 0) {
      SolverOptions more;
      more.max_sweeps = o.max_sweeps - o.sweeps;
      more.tolerance = o.tolerance;
      more.record_theta = false;
      const SolveResult mr = solver.solve(p, fr.lambda, more);
      high = mr.status == SolveStatus::Converged ? o.sweeps + mr.sweeps : -1;
    }
    rec.sweeps_to_tol_high.push_back(high);
  }
  for (int k = 0; k < o.sweeps; ++k)
    rec.theta.push_back(k < static_cast<int>(fr.theta.size()) ? static_cast<float>(fr.theta[static_cast<size_t>(k)])
                                                              : 0.0f);

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
  return fr.lambda;
}

/// The reference λ of a step without the tight oracle: builtin + PGS to tol / 100.
OracleSolution cheap_reference(const World& w, const LcpProblem& p, const LcpSolver& solver, const BenchOptions& o) {
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
void warm_up(World& w, const LcpSolver& solver, const BenchOptions& o) {
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
  if (o.warmstarts.empty()) throw ConfigError("bench: no warm starters selected");
  if (o.seeds.empty()) throw ConfigError("bench: no scene seeds selected");
  if (o.sweeps < 1) throw ConfigError("bench: --sweeps must be >= 1");
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance)) throw ConfigError("bench: --tol must be a finite number > 0");
  o.scene.validate();
  const auto wall0 = Clock::now();

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
  const auto solver = make_solver(o.solver);

  // Validate every name before the long run starts.
  for (const auto& name : o.warmstarts) {
    auto ws = registry.make(name, o.env);
    StarterRecord rec;
    rec.name = ws->name();
    rec.uses_oracle = ws->uses_oracle();
    if (rec.uses_oracle && !o.oracle)
      throw ConfigError("bench: warm starter '" + rec.name + "' needs the oracle, which this run skips (--no-oracle)");
    r.starters.push_back(std::move(rec));
  }
  const int steps = o.scene.time.steps;
  const long total = static_cast<long>(o.seeds.size()) * std::max(0, steps - o.warmup_steps) *
                     (o.mode == Mode::Paired ? 1 : static_cast<long>(o.warmstarts.size()));
  long done = 0;
  StepOutcome outcome;  // reused by every evaluation

  for (const std::uint64_t seed : o.seeds) {
    WorldDef def = o.scene;
    def.bodies.seed = seed;
    WarmStartEnv env = o.env;
    env.seed = o.env.seed ^ (seed * 0x9e3779b97f4a7c15ULL);
    std::vector<std::unique_ptr<WarmStarter>> starters;
    for (const auto& name : o.warmstarts) starters.push_back(registry.make(name, env));

    if (o.mode == Mode::Paired) {
      World ref(def);
      warm_up(ref, *solver, o);
      const bool record = seed == o.seeds.front();  // the report shows a frame of it
      if (record) {
        r.reference = std::make_shared<TrajectoryRecorder>(ref);
        r.reference_scene = scene_to_toml(def);
      }
      const auto oracle_starter = default_warm_starters().make("builtin");
      for (int s = o.warmup_steps; s < steps; ++s) {
        auto ts = Clock::now();
        ref.collide();
        const double collide_ms = ms_since(ts);
        ts = Clock::now();
        ref.assemble();
        const LcpProblem& p = solver->needs_assembled_matrix() ? ref.ensure_assembled_matrix() : ref.problem();
        const double assemble_ms = ms_since(ts);
        if (p.rows() == 0) {
          ++r.skipped_steps;
          ref.integrate(Eigen::VectorXd());
          if (record) {
            StepReport nothing;  // no contacts: nothing to solve
            nothing.solve.status = SolveStatus::Converged;
            r.reference->record_step(ref, nothing);
          }
        } else {
          r.collide_ms.push_back(collide_ms);
          r.assemble_ms.push_back(assemble_ms);
          // One shared oracle per step, started from the previous step's λ* matched by key
          // (cheaper; the oracle's cost is reported apart and never enters a total).
          auto t0 = Clock::now();
          const Eigen::VectorXd oracle_guess = oracle_starter->initial_guess(StepView{ref, nullptr});
          const OracleSolution os = o.oracle ? solve_oracle(p, &oracle_guess) : cheap_reference(ref, p, *solver, o);
          r.oracle_ms.push_back(ms_since(t0));
          r.oracle_residual.push_back(os.residual);
          r.step_seed.push_back(seed);
          r.step_index.push_back(s);
          r.step_rows.push_back(p.rows());
          for (std::size_t i = 0; i < starters.size(); ++i)
            evaluate_starter(ref, *starters[i], os.lambda, true, *solver, o, r.budgets, r.starters[i], outcome);
          ts = Clock::now();
          ref.integrate(os.lambda);
          r.integrate_ms.push_back(ms_since(ts));
          if (record) {
            StepReport rep;
            rep.contacts = static_cast<int>(ref.contacts().size());
            rep.rows = p.rows();
            rep.solve.status = os.accurate ? SolveStatus::Converged : SolveStatus::SweepLimit;
            rep.solve.residual = os.residual;
            r.reference->record_step(ref, rep);
          }
        }
        if (progress) progress(++done, total, "seed " + std::to_string(seed) + " step " + std::to_string(s + 1));
      }
    } else {
      for (std::size_t i = 0; i < starters.size(); ++i) {
        World w(def);
        warm_up(w, *solver, o);
        for (int s = o.warmup_steps; s < steps; ++s) {
          auto ts = Clock::now();
          w.collide();
          const double collide_ms = ms_since(ts);
          ts = Clock::now();
          w.assemble();
          const LcpProblem& p = solver->needs_assembled_matrix() ? w.ensure_assembled_matrix() : w.problem();
          const double assemble_ms = ms_since(ts);
          if (p.rows() == 0) {
            if (i == 0) ++r.skipped_steps;
            w.integrate(Eigen::VectorXd());
          } else {
            const OracleSolution os = o.oracle ? solve_oracle(p) : cheap_reference(w, p, *solver, o);
            if (i == 0) {
              r.step_seed.push_back(seed);
              r.step_index.push_back(s);
            }
            // In rollout mode each starter computes its own oracle (reported as its cost).
            const Eigen::VectorXd lam =
                evaluate_starter(w, *starters[i], os.lambda, false, *solver, o, r.budgets, r.starters[i], outcome);
            ts = Clock::now();
            w.integrate(lam);
            if (i == 0) {
              r.collide_ms.push_back(collide_ms);
              r.assemble_ms.push_back(assemble_ms);
              r.integrate_ms.push_back(ms_since(ts));
            }
          }
          if (progress) progress(++done, total, r.starters[i].name + " seed " + std::to_string(seed));
        }
      }
    }
  }
  r.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  return r;
}

Quartiles quartiles(std::vector<double> v) {
  Quartiles q;
  if (v.empty()) {
    q.q1 = q.median = q.q3 = std::numeric_limits<double>::quiet_NaN();
    return q;
  }
  std::sort(v.begin(), v.end());
  auto at = [&](double f) { return quantile_sorted(v, f); };
  q.q1 = at(0.25);
  q.median = at(0.5);
  q.q3 = at(0.75);
  return q;
}

std::vector<StarterSummary> summarise(const BenchResults& r) {
  std::vector<StarterSummary> out;
  const int never = r.options.sweeps + 1;
  for (const StarterRecord& rec : r.starters) {
    StarterSummary s;
    s.name = rec.name;
    s.uses_oracle = rec.uses_oracle;
    std::vector<double> sw, total;
    int unconv = 0;
    for (std::size_t k = 0; k < rec.sweeps_to_tol.size(); ++k) {
      const int v = rec.sweeps_to_tol[k];
      if (v < 0) ++unconv;
      sw.push_back(v < 0 ? never : v);
      total.push_back(rec.warmstart_ms[k] + rec.solve_ms[k]);
    }
    s.sweeps_to_tol = quartiles(sw);
    s.median_sweeps_to_tol = s.sweeps_to_tol.median;
    s.unconverged_share = sw.empty() ? 0.0 : static_cast<double>(unconv) / static_cast<double>(sw.size());
    s.warmstart_ms = quartiles(rec.warmstart_ms).median;
    s.oracle_ms = rec.uses_oracle && r.options.mode == Mode::Paired ? quartiles(r.oracle_ms).median
                                                                    : quartiles(rec.oracle_ms).median;
    s.solve_ms = quartiles(rec.solve_ms).median;
    s.total_ms = quartiles(total).median;
    s.ns_per_row_sweep = quartiles(rec.sweep_ns_per_row).median;
    s.initial_error = quartiles(rec.initial_error).median;
    const std::size_t nb = r.budgets.size();
    const auto bi = static_cast<std::size_t>(std::find(r.budgets.begin(), r.budgets.end(), r.options.budget) - r.budgets.begin());
    std::vector<double> at_b, at_cap;
    for (std::size_t k = 0; nb > 0 && k + 1 <= rec.residual.size() / nb; ++k) {
      if (bi < nb) at_b.push_back(rec.residual[k * nb + bi]);
      at_cap.push_back(rec.residual[k * nb + nb - 1]);
    }
    s.residual_at_budget = quartiles(at_b).median;
    s.residual_at_cap = quartiles(at_cap).median;
    if (!rec.sweeps_to_tol_high.empty()) {
      std::vector<double> hi;
      int un = 0;
      for (const int v : rec.sweeps_to_tol_high) {
        if (v < 0) ++un;
        hi.push_back(v < 0 ? r.options.max_sweeps + 1 : v);
      }
      s.median_sweeps_high = quartiles(hi).median;
      s.unconverged_share_high = static_cast<double>(un) / static_cast<double>(hi.size());
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace dc::bench
