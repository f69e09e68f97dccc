// prox-newton settings side by side on the engine's scene families (docs/solvers.md
// "prox-newton"): a scene advanced as `deepcontact bench --warmup-steps W` does (builtin +
// pgs-colored, 1000 sweeps, θ ≤ 1e-2 N), then for each evaluated step every variant solves the
// same LCP from the builtin guess to R/100 (R = 1e-6 of the heaviest body's weight, the bench's
// --accuracy trace target; --stop-factor 1: to R), the variants alternated step by step; the world advances with the
// oracle's λ*. Per variant and step: factorisations as the bench counts them (passes, short
// finish and proximal-finish iterations), lead-stage sweeps, Newton iterations, R/scale reached,
// CPU ms of this thread for the solve and to R (its first checkpoint at R, the checkpoints' own
// residual evaluations excluded), the iterations there (lead sweeps + Newton, it_to_R) and the
// factorisations there (fact_to_R, through checkpoint_stats; the whole run when R is never met); pgs from the same guess to θ ≤ 1e-2 N (cap 10,000) as the
// reference time.
//
//   build/bin/prox_families --scene scenes/pour.toml --seeds 3 --first 200 --steps 2
//       --variant base --variant pcg:stale_factor_iterations=10
// A variant is NAME[:key=value,...] over the ProxNewtonDef fields listed in apply(), and
// route.FIELD=value over the proximal finish's (both routes) listed in apply_route(); the variant
// `nncg` and `nncg-colored` (no keys) are plain nncg and nncg-colored under the same protocol
// (the references of the lead stage; lead_sweep=colored runs the lead on nncg-colored); their
// `lead` column is the run's sweeps.
#include <time.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace {

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

struct Variant {
  std::string name;
  dc::ProxNewtonDef def;
};

void apply_route(dc::ProximalPointDef& r, const std::string& key, double x) {
  if (key == "stale_factor_iterations") r.newton_sparse.stale_factor_iterations = static_cast<int>(x);
  else if (key == "krylov_max") r.newton_sparse.krylov_max = static_cast<int>(x);
  else if (key == "stale_accept") r.newton_sparse.stale_accept = x;
  else if (key == "fallback_doublings") r.newton_sparse.fallback_doublings = static_cast<int>(x);
  else if (key == "newton_stalls" || key == "ns_max_stalls") r.newton_sparse.max_stalls = static_cast<int>(x);
  else if (key == "stop_at_target") r.stop_at_target = x != 0;
  else if (key == "fallback_cap_fall") r.newton_sparse.fallback_cap_fall = x;
  else if (key == "fallback_sweeps") r.newton_sparse.fallback_sweeps = static_cast<int>(x);
  else if (key == "fallback_momentum") r.newton_sparse.fallback_momentum = x != 0;
  else if (key == "coupled_lu") r.newton_sparse.coupled_lu = x != 0;
  else if (key == "max_damping") r.newton_sparse.max_damping = x;
  else if (key == "max_backtracks") r.newton_sparse.max_backtracks = static_cast<int>(x);
  else if (key == "nonmonotone_window") r.newton_sparse.nonmonotone_window = static_cast<int>(x);
  else if (key == "inner_iterations") r.inner_iterations = static_cast<int>(x);
  else if (key == "krylov_forcing") r.newton_sparse.krylov_forcing = x;
  else if (key == "inner_forcing") r.inner_forcing = x;
  else if (key == "initial_shift") r.initial_shift = x;
  else if (key == "min_shift") r.min_shift = x;
  else if (key == "shrink") r.shrink = x;
  else if (key == "max_outer") r.max_outer = static_cast<int>(x);
  else if (key == "floor_decay") r.floor_decay = x;
  else if (key == "progress_window") r.progress_window = static_cast<int>(x);
  else if (key == "progress_factor") r.progress_factor = x;
  else if (key == "release_floor") r.release_floor = x != 0;
  else if (key == "window_stops") r.window_stops = x != 0;
  else if (key == "initial_floor") r.initial_floor = x;
  else if (key == "floor_stalls") r.floor_stalls = static_cast<int>(x);
  else throw dc::ConfigError("prox_families: unknown key 'route." + key + "'");
}

void apply(dc::ProxNewtonDef& d, const std::string& key, const std::string& value) {
  if (key == "lead_sweep") {  // natural | colored | auto
    if (value != "natural" && value != "colored" && value != "auto")
      throw dc::ConfigError("prox_families: lead_sweep=natural|colored|auto");
    d.lead_sweep = value == "colored" ? dc::ProxLeadSweep::Colored
                   : value == "auto"  ? dc::ProxLeadSweep::Auto
                                      : dc::ProxLeadSweep::Natural;
    return;
  }
  const double x = std::stod(value);
  if (key == "lead_sweeps") d.lead_sweeps = static_cast<int>(x);
  else if (key == "lead_finish_window") d.lead_finish_window = static_cast<int>(x);
  else if (key == "lead_colored_rows") d.lead_colored_rows = static_cast<int>(x);
  else if (key == "lead_gain") d.lead_gain = x;
  else if (key == "lead_window") d.lead_window = static_cast<int>(x);
  else if (key == "lead_window_gain") d.lead_window_gain = x;
  else if (key == "lead_window_gain_above") d.lead_window_gain_above = x;
  else if (key == "lead_stall_chunks") d.lead_stall_chunks = static_cast<int>(x);
  else if (key == "degenerate_rows") d.degenerate_rows = x;
  else if (key == "degenerate_stall_chunks") d.degenerate_stall_chunks = static_cast<int>(x);
  else if (key == "degenerate_fallback_momentum") d.degenerate_fallback_momentum = x != 0;
  else if (key == "probe_sweeps") d.probe_sweeps = static_cast<int>(x);
  else if (key == "probe_iterations") d.probe_iterations = static_cast<int>(x);
  else if (key == "probe_reach") d.probe_reach = x;
  else if (key == "probe_count") d.probe_count = static_cast<int>(x);
  else if (key == "probe_refall") d.probe_refall = x;
  else if (key == "probe_shift") d.probe_shift = x;
  else if (key == "degenerate_drift_jumps") d.degenerate_drift_jumps = static_cast<int>(x);
  else if (key == "degenerate_drift_linearity") d.degenerate_drift_linearity = x;
  else if (key == "lead_fallback_doublings") d.lead_fallback_doublings = static_cast<int>(x);
  else if (key == "lead_fallback_cap_fall") d.lead_fallback_cap_fall = x;
  else if (key == "lead_newton_stalls") d.lead_newton_stalls = static_cast<int>(x);
  else if (key == "lead_initial_shift") d.lead_initial_shift = x;
  else if (key == "lead_window_bodies") d.lead_window_bodies = x;
  else if (key == "safeguard_sweeps") d.safeguard_sweeps = static_cast<int>(x);
  else if (key == "newton_budget") d.newton_budget = static_cast<int>(x);
  else if (key == "pivot_rows") d.pivot_rows = static_cast<int>(x);
  else if (key == "continuation_stages") d.continuation_stages = static_cast<int>(x);
  else if (key == "continuation_first") d.continuation_first = x;
  else if (key == "continuation_within") d.continuation_within = x;
  else if (key == "local_pivot_rows") d.local_pivot_rows = static_cast<int>(x);
  else if (key == "local_pivot_rings") d.local_pivot_rings = static_cast<int>(x);
  else if (key == "local_pivot_threshold") d.local_pivot_threshold = x;
  else if (key == "local_pivot_shift") d.local_pivot_shift = x;
  else if (key == "local_pivot_rounds") d.local_pivot_rounds = static_cast<int>(x);
  else if (key == "newton_budget_lead_fall") d.newton_budget_lead_fall = x;
  else if (key == "newton_budget_gain") d.newton_budget_gain = x;
  else if (key == "guess_route_from_floor") d.guess_route_from_floor = x != 0;
  else if (key == "guess_fallback_cap_fall") d.guess_fallback_cap_fall = x;
  else if (key == "guess_floor_stalls") d.guess_floor_stalls = static_cast<int>(x);
  else if (key == "body_inner_iterations") d.body_inner_iterations = static_cast<int>(x);
  else if (key == "inner_tolerance") d.inner_tolerance = x;
  else if (key == "min_shift") d.min_shift = x;
  else if (key == "initial_shift") d.initial_shift = x;
  else if (key == "max_stalls") d.max_stalls = static_cast<int>(x);
  else if (key == "max_outer") d.max_outer = static_cast<int>(x);
  else if (key == "coupled_bounds") d.coupled_bounds = x != 0;
  else if (key == "proximal_finish") d.proximal_finish = x != 0;
  else if (key == "finish_iterations") d.finish_iterations = static_cast<int>(x);
  else if (key == "stale_factor_iterations") d.stale_factor_iterations = static_cast<int>(x);
  else if (key == "body_finish") d.body_finish = x != 0;
  else if (key == "exact_cone") d.exact_cone = x != 0;
  else if (key == "cone_shift") d.cone_shift = x;
  else if (key == "cone_inner_iterations") d.cone_inner_iterations = static_cast<int>(x);
  else if (key == "cone_inner_tolerance") d.cone_inner_tolerance = x;
  else if (key == "cone_anderson") d.cone_anderson = static_cast<int>(x);
  else if (key == "cone_shrink") d.cone_shrink = x;
  else if (key == "cone_min_shift") d.cone_min_shift = x;
  else if (key == "cone_follow_shift") d.cone_follow_shift = x != 0;
  else if (key == "cone_follow_after") d.cone_follow_after = static_cast<int>(x);
  else if (key == "cone_follow_iterations") d.cone_follow_iterations = static_cast<int>(x);
  else if (key == "cone_follow_below") d.cone_follow_below = x;
  else if (key == "cone_trust_radius") d.cone_trust_radius = x;
  else if (key == "cone_trust_grow") d.cone_trust_grow = x;
  else if (key == "cone_trust_forget") d.cone_trust_forget = x;
  else if (key == "cone_trust_accept") d.cone_trust_accept = x;
  else if (key == "cone_trust_retries") d.cone_trust_retries = static_cast<int>(x);
  else if (key == "cone_max_stalls") d.cone_max_stalls = static_cast<int>(x);
  else if (key == "body_finish_iterations") d.body_finish_iterations = static_cast<int>(x);
  else if (key.rfind("route.", 0) == 0) {
    // route.FIELD: the proximal finish's settings, in body space (finish_route) and in the dual
    // form (dual_finish_route) alike
    for (dc::ProximalPointDef* r : {&d.finish_route, &d.dual_finish_route}) apply_route(*r, key.substr(6), x);
  }
  else throw dc::ConfigError("prox_families: unknown key '" + key + "'");
}

Variant parse_variant(const std::string& spec) {
  Variant v;
  const auto colon = spec.find(':');
  v.name = spec.substr(0, colon);
  if (colon == std::string::npos) return v;
  std::stringstream ss(spec.substr(colon + 1));
  std::string kv;
  while (std::getline(ss, kv, ',')) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw dc::ConfigError("prox_families: variant key without '=': " + kv);
    apply(v.def, kv.substr(0, eq), kv.substr(eq + 1));
  }
  return v;
}

double weight_scale(const dc::LcpProblem& p, dc::Vec2 g) {
  const double gn = std::sqrt(g.x * g.x + g.y * g.y);
  double heaviest = 0.0;
  for (int k = 0; k + 1 < p.inv_mass.size(); k += 3)
    if (p.inv_mass[k] > 0) heaviest = std::max(heaviest, 1.0 / p.inv_mass[k]);
  return heaviest * gn > 0 ? heaviest * gn : 1.0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"prox-newton variants on an engine scene's steps"};
  std::string scene;
  std::vector<std::string> specs;
  int first = 0, steps = 1;
  std::vector<int> seeds{3};
  double accuracy = 1e-6;
  double stop_factor = 100;
  int checkpoint_every = 1;
  app.add_option("--scene", scene)->required();
  app.add_option("--variant", specs)->required();
  app.add_option("--first", first);
  app.add_option("--steps", steps);
  app.add_option("--seeds", seeds);
  app.add_option("--accuracy", accuracy);
  app.add_option("--stop-factor", stop_factor,
                 "the solver's tolerance is R·scale/this (default 100, the bench's trace; 1 = stop at R)");
  app.add_option("--checkpoint-every", checkpoint_every,
                 "checkpoints (the residual looks that time R) every this many iterations (default 1); a "
                 "colour-ordered solver maps λ back to row order at each, which the solve's time includes");
  CLI11_PARSE(app, argc, argv);
  std::vector<Variant> variants;
  for (const auto& s : specs) variants.push_back(parse_variant(s));
  std::printf("seed step rows variant reached R_over_scale factorisations lead newton finish outer cpu_ms ms_to_R it_to_R pgs_ms fact_to_R message\n");
  for (const int seed : seeds) {
    dc::WorldDef def = dc::load_scene(scene);
    def.bodies.seed = static_cast<std::uint64_t>(seed);
    dc::World w(def);
    const auto builtin = dc::default_warm_starters().make("builtin", dc::WarmStartEnv{});
    const auto warm_solver = dc::make_solver("pgs-colored");
    const auto pgs = dc::make_solver("pgs");
    dc::SolverOptions warm;
    warm.max_sweeps = 1000;
    warm.tolerance = 1e-2;
    warm.record_theta = false;
    for (int k = 0; k < first; ++k) {
      w.collide();
      const dc::LcpProblem& p = w.assemble();
      if (p.rows() == 0) {
        w.integrate(Eigen::VectorXd());
        continue;
      }
      w.integrate(warm_solver->solve(p, builtin->initial_guess(dc::StepView{w, nullptr}), warm).lambda);
    }
    std::vector<std::unique_ptr<dc::LcpSolver>> solvers;
    for (const auto& v : variants)
      solvers.push_back(v.name == "nncg" || v.name == "nncg-colored"
                            ? dc::make_solver(v.name)
                            : std::unique_ptr<dc::LcpSolver>(std::make_unique<dc::ProxNewtonSolver>(v.def)));
    for (int s = first; s < first + steps; ++s) {
      w.collide();
      const dc::LcpProblem& p = w.assemble();
      if (p.rows() == 0) {
        w.integrate(Eigen::VectorXd());
        continue;
      }
      const Eigen::VectorXd guess = builtin->initial_guess(dc::StepView{w, nullptr});
      const double scale = weight_scale(p, def.world.gravity);
      dc::SolverOptions po;
      po.max_sweeps = 10000;
      po.tolerance = 1e-2;
      po.record_theta = false;
      const double p0 = thread_cpu_ms();
      (void)pgs->solve(p, guess, po);
      const double pgs_ms = thread_cpu_ms() - p0;
      for (std::size_t i = 0; i < variants.size(); ++i) {
        dc::SolverOptions so;
        so.max_sweeps = 10000;
        so.tolerance = accuracy * scale / stop_factor;
        so.record_theta = false;
        // ms to R: CPU time at the first checkpoint whose λ is at R (the checkpoints' own
        // residual evaluations excluded), as the bench's trace takes it.
        for (int k = checkpoint_every; k <= so.max_sweeps; k += std::max(1, checkpoint_every)) so.checkpoints.push_back(k);
        double callback_ms = 0.0, to_r_ms = -1.0, t0 = 0.0;
        int to_r_it = -1;  // iterations (lead sweeps + Newton) at the first checkpoint at R
        int to_r_fact = -1;  // factorisations there (ProxNewtonSolver::checkpoint_stats)
        const auto* pn_run = dynamic_cast<const dc::ProxNewtonSolver*>(solvers[i].get());
        so.on_checkpoint = [&](int it, const Eigen::VectorXd& lam) {
          if (to_r_ms >= 0) return;
          const double c0 = thread_cpu_ms();
          if (dc::natural_residual(p, lam) / scale <= accuracy) {
            to_r_ms = c0 - t0 - callback_ms;
            to_r_it = it;
            to_r_fact = pn_run != nullptr ? pn_run->checkpoint_stats().factorizations : 0;
          }
          callback_ms += thread_cpu_ms() - c0;
        };
        t0 = thread_cpu_ms();
        const dc::SolveResult r = solvers[i]->solve(p, guess, so);
        const double ms = thread_cpu_ms() - t0 - callback_ms;
        if (to_r_ms < 0 && dc::natural_residual(p, r.lambda) / scale <= accuracy) {
          to_r_ms = ms;
          to_r_it = r.sweeps;
          to_r_fact = pn_run != nullptr ? pn_run->last_stats().factorizations : 0;
        }
        const auto* pn = dynamic_cast<const dc::ProxNewtonSolver*>(solvers[i].get());
        const dc::ProxNewtonStats st = pn != nullptr ? pn->last_stats() : dc::ProxNewtonStats{};
        const double acc = dc::natural_residual(p, r.lambda) / scale;
        std::printf("%d %d %d %s %d %.3g %d %d %d %d %d %.1f %.2f %d %.2f %d \"%s\"\n", seed, s, p.rows(), variants[i].name.c_str(),
                    acc <= accuracy ? 1 : 0, acc, st.factorizations, pn != nullptr ? st.lead_sweeps : r.sweeps, st.newton,
                    st.finish_newton, st.outer, ms, to_r_ms, to_r_it, pgs_ms, to_r_fact, r.message.c_str());
        std::fflush(stdout);
      }
      const dc::OracleSolution os = dc::solve_oracle(p, &guess);
      w.integrate(os.lambda);
    }
  }
  return 0;
}
