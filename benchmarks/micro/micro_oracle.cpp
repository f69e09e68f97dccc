// Google Benchmark of the oracle λ* (dc/warmstart/oracle.hpp: solve_oracle) on the seed scene's
// steps as the bench asks for them: the seed scene (seed 1, 600 steps) advanced with λ*, each
// step's LCP solved from the previous step's λ* matched by key (the builtin starter), so every
// route below sees the same problems and the same guesses (recorded once, by route 7: nncg to
// θ ≤ 1e-9 N, newton-sparse and prox-newton to their own solution test; a fixed route, so that
// the steps do not move with the route being measured: through the impact a λ* that differs
// within the tolerance already changes the later steps).
//
//   BM_Oracle/route:R  all recorded steps solved by route R, once per benchmark iteration:
//                      route 0 is OracleOptions{} (the route of the bench and the copy starter),
//                      routes 1… are kRoutes below (stage 1 solver, sweep cap, θ; stage 2; stage 3;
//                      whether stages 2 and 3 stop once the oracle accepts)
//   Counters: ms_per_step (CPU time of this thread per step, mean), median_ms (per step),
//   p90_ms, accurate (share of steps within the oracle's tolerance), worst_residual [N].
//
//   build/bin/micro_oracle --benchmark_min_time=1x   (one pass over the steps per route)
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "dc/engine/scene.hpp"
#include "dc/engine/world.hpp"
#include "dc/warmstart/oracle.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace {

dc::OracleOptions route(int r);
constexpr int kReferenceRoute = 7;  ///< the route whose λ* advances the recorded scenes

struct RecordedStep {
  dc::LcpProblem problem;
  Eigen::VectorXd guess;  ///< previous step's λ* matched by key (builtin)
};

/// Steps [first, last) of a scene advanced with route kReferenceRoute's λ* (the steps before
/// `first` with builtin + 300 PGS sweeps to θ ≤ 1e-2 N, as the bench's warm-up).
std::vector<RecordedStep> record(const dc::WorldDef& def, int first, int last) {
  std::vector<RecordedStep> out;
  const dc::OracleOptions reference = route(kReferenceRoute);
  dc::World w(def);
  const auto builtin = dc::default_warm_starters().make("builtin", dc::WarmStartEnv{});
  const auto pgs = dc::make_solver("pgs");
  dc::SolverOptions warm;
  warm.max_sweeps = 300;
  warm.tolerance = 1e-2;
  warm.record_theta = false;
  for (int k = 0; k < first; ++k)
    w.step(*pgs, warm, dc::World::WarmStart::PreviousLambda);
  {
    for (int k = first; k < last; ++k) {
      w.collide();
      const dc::LcpProblem& p = w.assemble();  // A not formed: as the bench's default (pgs) run
      if (p.rows() == 0) {
        w.integrate(Eigen::VectorXd());
        continue;
      }
      Eigen::VectorXd guess = builtin->initial_guess(dc::StepView{w, nullptr});
      const dc::OracleSolution os = dc::solve_oracle(p, &guess, reference);
      out.push_back({p, std::move(guess)});
      w.integrate(os.lambda);
    }
  }
  return out;
}

/// Scene 0: the seed scene's 600 steps; 1: impact (250 bodies, seed 5) through the impact,
/// steps 195–204.
const std::vector<RecordedStep>& scene_steps(int scene) {
  static const std::vector<RecordedStep> seed = record(dc::default_world_def(), 0, dc::default_world_def().time.steps);
  if (scene == 0) return seed;
  static const std::vector<RecordedStep> impact = [] {
    dc::WorldDef def = dc::load_scene(std::string(DC_SOURCE_DIR) + "/scenes/impact.toml");
    def.bodies.seed = 5;  // as `bench --seeds 5`
    return record(def, 195, 205);
  }();
  return impact;
}

/// The routes BM_Oracle compares besides OracleOptions{} (route 0): stage 1's iterative solver
/// ("" = none), its sweep cap and θ [N], stage 2, stage 3, OracleOptions::stop_when_accepted.
struct Route {
  const char* iterative;
  int sweeps;
  double theta;
  const char* solver;
  int solver_iterations;
  const char* fallback;
  bool stop_when_accepted = true;
};
constexpr Route kRoutes[] = {
    {"nncg", 5000, 1e-11, "newton-sparse", 0, "newton"},  // 1: nncg to a tight θ, then newton-sparse
    {"nncg", 2000, 1e-9, "prox-newton", 0, "newton"},     // 2: a looser stage 1, then prox-newton
    {"nncg", 2000, 1e-9, "newton-sparse", 0, "newton"},   // 3: a looser stage 1, then newton-sparse
    {"nncg", 2000, 1e-9, "newton-sparse", 30, "prox-newton"},  // 4: newton-sparse ≤ 30, then prox-newton
    {"", 0, 0.0, "prox-newton", 0, "newton-sparse"},      // 5: no stage 1
    {"", 0, 0.0, "newton-sparse", 10, "prox-newton"},     // 6: no stage 1
    {"nncg", 2000, 1e-9, "newton-sparse", 10, "prox-newton", false},  // 7: θ ≤ 1e-9, to the solution test
};

dc::OracleOptions route(int r) {
  dc::OracleOptions o;
  if (r == 0) return o;
  const Route& x = kRoutes[r - 1];
  o.iterative = x.iterative;
  o.polish_sweeps = x.sweeps;
  o.polish_theta = x.theta;
  o.solver = x.solver;
  o.solver_iterations = x.solver_iterations;
  o.fallback_solver = x.fallback;
  o.stop_when_accepted = x.stop_when_accepted;
  return o;
}

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

void BM_Oracle(benchmark::State& state) {
  const auto& steps = scene_steps(static_cast<int>(state.range(0)));
  const dc::OracleOptions o = route(static_cast<int>(state.range(1)));
  std::vector<double> ms;
  int accurate = 0;
  double worst = 0.0;
  for (auto _ : state) {
    ms.clear();
    accurate = 0;
    worst = 0.0;
    for (const RecordedStep& s : steps) {
      const double t0 = thread_cpu_ms();
      const dc::OracleSolution os = dc::solve_oracle(s.problem, &s.guess, o);
      ms.push_back(thread_cpu_ms() - t0);
      accurate += os.accurate ? 1 : 0;
      worst = std::max(worst, os.residual);
    }
  }
  const auto n = static_cast<double>(steps.size());
  double total = 0.0;
  for (double x : ms) total += x;
  std::sort(ms.begin(), ms.end());
  state.counters["steps"] = n;
  state.counters["ms_per_step"] = total / n;
  state.counters["median_ms"] = ms[ms.size() / 2];
  state.counters["p90_ms"] = ms[static_cast<std::size_t>(0.9 * static_cast<double>(ms.size() - 1))];
  state.counters["accurate"] = accurate / n;
  state.counters["worst_residual"] = worst;
}

}  // namespace

BENCHMARK(BM_Oracle)
    ->ArgNames({"scene", "route"})
    ->ArgsProduct({{0, 1}, benchmark::CreateDenseRange(0, static_cast<int>(std::size(kRoutes)), 1)})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_MAIN();
