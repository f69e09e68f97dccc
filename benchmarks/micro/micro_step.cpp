// Google Benchmark of the stages of one World::step (linear step cost, docs/design.md §8.4)
// on the seed scene family scaled to n circles at the seed's density (box side 3√n m,
// σ = 0.465√n m, r = 1, μ = 0.5, Δt = 0.01; benchmarks/scripts/step-scaling.sh), settled for
// kSettleSteps steps once per n, then each stage timed on that state: BM_Collide,
// BM_BroadPhase, BM_Assemble, BM_WarmStart, BM_Solve, BM_Integrate, BM_Record, BM_Step
// (`simulate --out`), BM_StepOnly (`simulate`); both steps use the builtin warm start. Last
// argument: 0 = creation order, 1 = Morton body order, 2 (whole step only) = the engine-internal
// Morton order, 3 (whole step only) = the default settings (`internal_order = "auto"`).
// Counter us_per_row = CPU time / LCP rows [µs], which must stay flat with the body count
// (docs/bench.md "Micro benchmarks"); zero_rows = the fraction of the pile's rows with λ = 0
// (the falling pile's is far higher at 10,000 bodies and more than at 1,000).
// BM_StepOnlySettled: BM_StepOnly on the pile built at rest (settled_pile.hpp), one regime at
// every size. BM_StepOnly and BM_StepOnlySettled step with "pgs"; BM_ColoredStepOnly and
// BM_ColoredStepOnlySettled are the same with the default solver, "pgs-colored". BM_StepStages: consecutive steps of the pile
// with "pgs" or "pgs-colored", each stage (and pgs-colored's set-up parts) in thread CPU time
// per contact row, and the heap allocations of each stage per step (counting_malloc.hpp);
// benchmarks/scripts/step-stages.py prints them as a table; BM_StepStagesSettled the same with
// pgs-colored on the pile built at rest, with sweep_mb, the bytes one sweep streams, and
// BM_ReadRate this core's read rate over as many megabytes. BM_ExternalOrder: the public
// contact order of the internal order (InternalBodyOrder::external_order) on the pile.
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "dc/engine/internal_body_order.hpp"
#include "dc/engine/trajectory_recorder.hpp"
#include "counting_malloc.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/engine/world.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "fixed_sweeps.hpp"
#include "settled_pile.hpp"

namespace {

constexpr int kSettleSteps = 150;
constexpr int kSettleSweeps = 20;
constexpr int kRestSteps = 100;  ///< steps that close the packed pile's gaps

/// `order`: 0 creation, 1 Morton numbering, 2 creation numbering with the internal order,
/// 3 creation numbering with the default internal order. `settled`: the pile built at rest.
dc::WorldDef scaled_seed_scene(int n, int order, bool settled) {
  dc::WorldDef def = settled ? dc::bench_micro::packed_pile(n, order == 1) : dc::stress::scaled_seed_pile(n);
  def.solver.sweeps = kSettleSweeps;
  def.bodies.order = order == 1 ? dc::BodyOrder::Morton : dc::BodyOrder::Creation;
  if (order != 3) def.bodies.internal_order = order == 2 ? dc::InternalOrder::Morton : dc::InternalOrder::None;
  return def;
}

using dc::bench_micro::fixed_sweeps;

/// The settled pile of n bodies, collided and assembled, with the builtin guess and the
/// 20-sweep solution of its current problem. Built on first use (a 40,000-body pile takes
/// seconds) and never changed afterwards.
struct Pile {
  std::unique_ptr<dc::World> world;
  Eigen::VectorXd guess, lambda;
};

const Pile& pile(int n, int morton, bool settled = false) {
  static std::map<std::tuple<int, int, bool>, Pile> piles;
  auto it = piles.find({n, morton, settled});
  if (it != piles.end()) return it->second;
  Pile p;
  p.world = std::make_unique<dc::World>(scaled_seed_scene(n, morton, settled));
  const auto solver = dc::make_solver("pgs");
  const auto builtin = dc::default_warm_starters().make("builtin");
  const dc::SolverOptions o = fixed_sweeps(kSettleSweeps);
  auto guess = [&](const dc::World& w) { return builtin->initial_guess(dc::StepView{w, nullptr}); };
  for (int k = 0; k < (settled ? kRestSteps : kSettleSteps); ++k) p.world->step(*solver, o, guess);
  p.world->collide();
  p.world->assemble();
  p.guess = guess(*p.world);
  p.lambda = solver->solve(p.world->problem(), p.guess, o).lambda;
  return piles.emplace(std::make_tuple(n, morton, settled), std::move(p)).first->second;
}

void report(benchmark::State& state, const dc::World& w) {
  const double rows = w.problem().rows();
  state.counters["bodies"] = static_cast<double>(w.bodies().size());
  state.counters["rows"] = rows;
  state.counters["us_per_row"] = benchmark::Counter(1e-6 * rows * static_cast<double>(state.iterations()),
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

int bodies_of(const benchmark::State& s) { return static_cast<int>(s.range(0)); }
/// The settled pile of the benchmark's arguments (bodies, [sweeps,] morton).
const Pile& pile_of(const benchmark::State& s, int morton_arg) {
  return pile(bodies_of(s), static_cast<int>(s.range(morton_arg)));
}

void BM_Collide(benchmark::State& state) {
  const Pile& p = pile_of(state, 1);
  dc::World w = *p.world;
  for (auto _ : state) benchmark::DoNotOptimize(w.collide().data());
  report(state, *p.world);
}

void BM_BroadPhase(benchmark::State& state) {
  const Pile& p = pile_of(state, 1);
  const dc::World& w = *p.world;
  const int n = static_cast<int>(w.bodies().size());
  std::vector<double> reach(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    reach[static_cast<std::size_t>(k)] = w.bodies().radius[static_cast<std::size_t>(k)] +
                                         dc::speculative_reach(w.bodies(), k, w.def().contact, w.def().time.dt);
  dc::UniformGridBroadPhase bp;
  std::vector<std::pair<int, int>> pairs;
  for (auto _ : state) {
    bp.find_pairs(w.bodies().position, reach, pairs);
    benchmark::DoNotOptimize(pairs.data());
  }
  state.counters["pairs"] = static_cast<double>(pairs.size());
  state.counters["tests"] = static_cast<double>(bp.last_pair_tests());
  double max_reach = 0;
  for (double r : reach) max_reach = std::max(max_reach, r);
  state.counters["max_reach"] = max_reach;
  report(state, w);
}

void BM_Assemble(benchmark::State& state) {
  const Pile& p = pile_of(state, 1);
  dc::World w = *p.world;
  for (auto _ : state) benchmark::DoNotOptimize(w.assemble().b.data());
  report(state, *p.world);
}

void BM_WarmStart(benchmark::State& state) {
  const Pile& p = pile_of(state, 1);
  const auto builtin = dc::default_warm_starters().make("builtin");
  for (auto _ : state) {
    Eigen::VectorXd g = builtin->initial_guess(dc::StepView{*p.world, nullptr});
    benchmark::DoNotOptimize(g.data());
  }
  report(state, *p.world);
}

void BM_Solve(benchmark::State& state) {
  const Pile& p = pile_of(state, 2);
  const auto solver = dc::make_solver("pgs");
  const dc::SolverOptions o = fixed_sweeps(static_cast<int>(state.range(1)));
  for (auto _ : state) {
    dc::SolveResult r = solver->solve(p.world->problem(), p.guess, o);
    benchmark::DoNotOptimize(r.lambda.data());
  }
  report(state, *p.world);
}

void BM_Integrate(benchmark::State& state) {
  const Pile& p = pile_of(state, 1);
  dc::World w = *p.world;  // copy-assigned back each iteration (reuses its memory, not timed)
  for (auto _ : state) {
    state.PauseTiming();
    w = *p.world;
    state.ResumeTiming();
    w.integrate(p.lambda);
    benchmark::DoNotOptimize(w.bodies().position.data());
  }
  report(state, *p.world);
}

/// The pile's contacts in an engine-internal order (the bodies Morton-sorted, the contacts
/// rekeyed) and InternalBodyOrder::external_order on them, the public order World translates
/// its contacts and rows by: keys read from the contacts (source 0) or from their assembled
/// constraints (source 1, what a step reads).
void BM_ExternalOrder(benchmark::State& state) {
  const dc::World& w = *pile(bodies_of(state), 0).world;
  dc::InternalBodyOrder order;
  order.update_from(w.bodies(), true);
  double max_radius = 0;
  for (const double r : w.bodies().radius) max_radius = std::max(max_radius, r);
  order.resort(2 * max_radius);
  std::vector<dc::Contact> internal = w.contacts();
  order.rekey(internal);
  dc::ContactConstraints assembled;
  for (const dc::Contact& c : internal) assembled.add(c.body_a < 0 ? -1 : c.body_a, c.body_b, 0.5, c.key.feature);
  const int n = static_cast<int>(w.bodies().size());
  std::vector<int> internal_of;
  for (auto _ : state) {
    if (state.range(1) == 1)
      order.external_order(internal, assembled, n, internal_of);
    else
      order.external_order(internal, n, internal_of);
    benchmark::DoNotOptimize(internal_of.data());
  }
  report(state, w);
}

void BM_Record(benchmark::State& state) {
  const Pile& p = pile_of(state, 1);
  dc::StepReport rep;
  rep.rows = p.world->problem().rows();
  rep.contacts = static_cast<int>(p.world->contacts().size());
  std::unique_ptr<dc::TrajectoryRecorder> rec;
  int recorded = 0;
  for (auto _ : state) {
    if (recorded % 50 == 0) {  // a fresh recorder every 50 steps: memory stays bounded
      state.PauseTiming();
      rec = std::make_unique<dc::TrajectoryRecorder>(*p.world);
      rec->reserve_steps(50);
      state.ResumeTiming();
    }
    rec->record_step(*p.world, rep);
    ++recorded;
  }
  report(state, *p.world);
}

void BM_Step(benchmark::State& state) {
  const Pile& p = pile_of(state, 2);
  const auto solver = dc::make_solver("pgs");
  const dc::SolverOptions o = fixed_sweeps(static_cast<int>(state.range(1)));
  std::unique_ptr<dc::TrajectoryRecorder> rec;
  dc::World w = *p.world;
  for (auto _ : state) {
    state.PauseTiming();
    w = *p.world;  // every iteration steps the same state (copy-assigned: memory reused)
    if (!rec || rec->steps() >= 50) {
      rec = std::make_unique<dc::TrajectoryRecorder>(w);
      rec->reserve_steps(50);
    }
    state.ResumeTiming();
    const dc::StepReport r = w.step(*solver, o, dc::World::WarmStart::PreviousLambda);
    rec->record_step(w, r);
    benchmark::DoNotOptimize(w.bodies().position.data());
  }
  report(state, *p.world);
}

/// BM_StepOnly on the falling pile or the pile built at rest, with the solver `solver`.
void step_only(benchmark::State& state, const Pile& p, const char* solver_name = "pgs") {
  const auto solver = dc::make_solver(solver_name);
  const dc::SolverOptions o = fixed_sweeps(static_cast<int>(state.range(1)));
  dc::World w = *p.world;
  // One untimed step first: the fresh solver builds its scratch (layout, colouring, packed
  // batches) and touches its pages there. Without it a run of one timed iteration — what
  // --benchmark_min_time=0.1 gives at 40,000 bodies, where that first step alone outlasts it —
  // reports the first step's set-up instead of a step's cost.
  w.step(*solver, o, dc::World::WarmStart::PreviousLambda);
  for (auto _ : state) {
    state.PauseTiming();
    w = *p.world;  // every iteration steps the same state (copy-assigned: memory reused)
    state.ResumeTiming();
    const dc::StepReport r = w.step(*solver, o, dc::World::WarmStart::PreviousLambda);
    benchmark::DoNotOptimize(r.solve.lambda.data());
  }
  report(state, *p.world);
  state.counters["resorts"] = w.internal_order_resorts() - p.world->internal_order_resorts();  // in the timed step
  const Eigen::Index zeros = (p.lambda.array() == 0.0).count();
  state.counters["zero_rows"] = p.lambda.size() > 0 ? static_cast<double>(zeros) / static_cast<double>(p.lambda.size()) : 0.0;
}

void BM_StepOnly(benchmark::State& state) { step_only(state, pile_of(state, 2)); }
void BM_StepOnlySettled(benchmark::State& state) {
  step_only(state, pile(bodies_of(state), static_cast<int>(state.range(2)), true));
}
/// BM_StepOnly and BM_StepOnlySettled with the engine's default solver, "pgs-colored".
void BM_ColoredStepOnly(benchmark::State& state) { step_only(state, pile_of(state, 2), "pgs-colored"); }
void BM_ColoredStepOnlySettled(benchmark::State& state) {
  step_only(state, pile(bodies_of(state), static_cast<int>(state.range(2)), true), "pgs-colored");
}

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Thread CPU seconds and allocations of the stages of consecutive steps.
struct StageTally {
  static constexpr int kStages = 5;  // collide, assemble, warm start, solve, integrate
  static constexpr const char* kName[kStages] = {"collide", "assemble", "warm", "solve", "integrate"};
  double seconds[kStages] = {};
  long allocs[kStages] = {};
  double t = 0;
  long a = 0;
  void begin() {
    a = dc::bench::AllocationCounter::count();
    t = thread_cpu_s();
  }
  void lap(int stage) {
    const double now = thread_cpu_s();
    const long an = dc::bench::AllocationCounter::count();
    seconds[stage] += now - t;
    allocs[stage] += an - a;
    t = now;
    a = an;
  }
};

/// The storage a stepping loop keeps from step to step: λ⁰, λ and the solve's outcome.
struct KeptStep {
  dc::KeptVector guess, lambda;
  dc::SolveResult result;
};

/// One step of w by its public stages (World::step's sequence; the builtin warm start and the
/// solve into storage kept from step to step, as World::step keeps its own), timed.
void timed_step(dc::World& w, dc::LcpSolver& solver, const dc::SolverOptions& o, dc::WarmStarter& builtin,
                KeptStep& kept, StageTally& tally) {
  tally.begin();
  w.collide();
  tally.lap(0);
  w.assemble();
  tally.lap(1);
  builtin.initial_guess_into(dc::StepView{w, nullptr}, kept.guess);
  tally.lap(2);
  solver.solve_into(w.problem(), kept.guess, o, kept.lambda, kept.result);
  tally.lap(3);
  w.integrate(kept.lambda);
  tally.lap(4);
}

/// One World::step of w (WarmStart::PreviousLambda: the builtin warm start, no public view),
/// timed whole in thread CPU time and split over the stages in the proportions of the step's
/// wall-clock profile (a world with an internal order builds its public views only when read,
/// so its stages are not timed one by one through the public calls). Allocations: the step's,
/// counted under "solve". Returns the step's rows.
int whole_step(dc::World& w, dc::LcpSolver& solver, const dc::SolverOptions& o, StageTally& tally) {
  tally.begin();
  const dc::StepReport r = w.step(solver, o, dc::World::WarmStart::PreviousLambda);
  const double cpu = thread_cpu_s() - tally.t;
  tally.lap(3);
  tally.seconds[3] -= cpu;
  const dc::StepProfile& pr = r.profile;
  const double ms[StageTally::kStages] = {pr.collide_ms, pr.assemble_ms, pr.warmstart_ms, pr.solve_ms,
                                          pr.integrate_ms};
  const double total = pr.total_ms();
  for (int s = 0; s < StageTally::kStages; ++s)
    tally.seconds[s] += total > 0 ? cpu * ms[s] / total : cpu / StageTally::kStages;
  return r.rows;
}

/// Consecutive steps of `p`'s world with "pgs" or "pgs-colored" (`colored`), from kWarmSteps
/// untimed steps on (steady state): counters ns_<stage> and, for pgs-colored, ns_solve_<part>
/// per contact row (thread CPU time), allocs_<stage> per step, and sweep_mb = the bytes one
/// sweep streams (PgsColoredProfile::sweep_bytes) in MB. `whole`: each step timed by whole_step
/// (needed with an internal order), else by its public stages (timed_step).
void step_stages(benchmark::State& state, const Pile& p, bool colored, bool whole) {
  constexpr int kWarmSteps = 3;
  dc::PgsColoredProfile prof;
  dc::PgsColoredDef def;
  def.profile = &prof;
  const auto solver = colored ? dc::make_pgs_colored(def) : dc::make_solver("pgs");
  const auto builtin = dc::default_warm_starters().make("builtin");
  const dc::SolverOptions o = fixed_sweeps(kSettleSweeps);
  dc::World w = *p.world;  // stepped on from the pile: a fixed iteration count keeps it near it
  StageTally tally;
  KeptStep kept;
  const auto one_step = [&] {  // the step's rows
    if (whole) return whole_step(w, *solver, o, tally);
    timed_step(w, *solver, o, *builtin, kept, tally);
    return w.problem().rows();
  };
  for (int k = 0; k < kWarmSteps; ++k) one_step();
  tally = StageTally{};
  prof = dc::PgsColoredProfile{};
  double rows = 0;
  long steps = 0;
  dc::bench::AllocationCounter::start();
  for (auto _ : state) {
    rows += one_step();
    ++steps;
  }
  dc::bench::AllocationCounter::stop();
  double total = 0;
  long allocs = 0;
  for (int s = 0; s < StageTally::kStages; ++s) {
    state.counters[std::string("ns_") + StageTally::kName[s]] = 1e9 * tally.seconds[s] / rows;
    state.counters[std::string("allocs_") + StageTally::kName[s]] = static_cast<double>(tally.allocs[s]) / steps;
    total += tally.seconds[s];
    allocs += tally.allocs[s];
  }
  state.counters["ns_total"] = 1e9 * total / rows;
  state.counters["allocs_step"] = static_cast<double>(allocs) / steps;
  state.counters["rows"] = rows / steps;
  if (colored) {
    const std::pair<const char*, double> parts[] = {
        {"checks", prof.checks}, {"coloring", prof.coloring}, {"ordering", prof.ordering}, {"pack", prof.pack},
        {"du0", prof.du0},       {"sweeps", prof.sweeps},     {"unpermute", prof.unpermute},
        {"residual", prof.residual}};
    for (const auto& [name, sec] : parts) state.counters[std::string("ns_solve_") + name] = 1e9 * sec / rows;
    state.counters["sweep_mb"] = 1e-6 * static_cast<double>(prof.sweep_bytes);
  }
}

/// step_stages on the falling pile (args: bodies, solver 0 = "pgs" / 1 = "pgs-colored", order 0
/// creation / 1 Morton numbering / 2 internal order, stepped by whole_step).
void BM_StepStages(benchmark::State& state) {
  step_stages(state, pile_of(state, 2), state.range(1) == 1, state.range(2) == 2);
}
/// step_stages with "pgs-colored" on the pile built at rest (args: bodies, order as
/// BM_StepOnlySettled's: 0 creation, timed by its public stages; 3 the default settings, timed
/// by whole_step at every size): where BM_ColoredStepOnlySettled's cost per row grows.
void BM_StepStagesSettled(benchmark::State& state) {
  const int order = static_cast<int>(state.range(1));
  step_stages(state, pile(bodies_of(state), order, true), true, order >= 2);
}

/// This core's read rate over `MB` megabytes (arg), read again and again as the sweeps read their
/// packed batches (sweep_mb of BM_StepStages*): counter gb_per_s. Where the rate falls from
/// the cache's to the memory's tells the size beyond which a sweep streams from memory.
void BM_ReadRate(benchmark::State& state) {
  std::vector<double> data(static_cast<std::size_t>(state.range(0)) << 17, 1.0);
  for (auto _ : state) {
    // Eight independent sums: the adds keep pace with the loads.
    double s[8] = {};
    for (std::size_t k = 0; k < data.size(); k += 8)
      for (int q = 0; q < 8; ++q) s[q] += data[k + static_cast<std::size_t>(q)];
    benchmark::DoNotOptimize(s);
    benchmark::ClobberMemory();
  }
  const double bytes = static_cast<double>(data.size() * sizeof(double)) * static_cast<double>(state.iterations());
  state.counters["gb_per_s"] = benchmark::Counter(1e-9 * bytes, benchmark::Counter::kIsRate);
}

/// Reads and writes one double per cache line of `data`, displacing from the caches what the
/// timed code would otherwise find there (as a step's other stages do).
void touch_lines(std::vector<double>& data) {
  double sum = 0;
  for (std::size_t k = 0; k < data.size(); k += 8) sum += data[k]++;
  benchmark::DoNotOptimize(sum);
}

/// pgs-colored's solve alone on the settled pile's problem (args: bodies, morton), 20 sweeps from
/// the builtin guess, with the caches evicted before each solve as the stages before it evict
/// them in a step: counters ns_<part> per contact row (thread CPU time) as BM_StepStages's
/// ns_solve_<part>, and ns_solve. Cheaper to repeat than BM_StepStages (no collide, assemble or
/// integrate), for comparing set-up and sweep variants.
void colored_solve_parts(benchmark::State& state, const Pile& p) {
  dc::PgsColoredProfile prof;
  dc::PgsColoredDef def;
  def.profile = &prof;
  const auto solver = dc::make_pgs_colored(def);
  const dc::SolverOptions o = fixed_sweeps(kSettleSweeps);
  const dc::LcpProblem& problem = p.world->problem();
  std::vector<double> evict(std::size_t{8} << 20, 1.0);  // 64 MB, beyond the last-level cache
  (void)solver->solve(problem, p.guess, o);
  prof = dc::PgsColoredProfile{};
  double solve_s = 0;
  for (auto _ : state) {
    state.PauseTiming();
    touch_lines(evict);
    state.ResumeTiming();
    const double t0 = thread_cpu_s();
    const dc::SolveResult r = solver->solve(problem, p.guess, o);
    solve_s += thread_cpu_s() - t0;
    benchmark::DoNotOptimize(r.lambda.data());
  }
  const double rows = static_cast<double>(problem.rows()) * static_cast<double>(state.iterations());
  state.counters["rows"] = problem.rows();
  state.counters["ns_solve"] = 1e9 * solve_s / rows;
  const std::pair<const char*, double> parts[] = {
      {"checks", prof.checks}, {"coloring", prof.coloring}, {"ordering", prof.ordering}, {"pack", prof.pack},
      {"du0", prof.du0},       {"sweeps", prof.sweeps},     {"unpermute", prof.unpermute},
      {"residual", prof.residual}};
  for (const auto& [name, sec] : parts) state.counters[std::string("ns_solve_") + name] = 1e9 * sec / rows;
}
void BM_ColoredSolveParts(benchmark::State& state) { colored_solve_parts(state, pile_of(state, 1)); }
/// BM_ColoredSolveParts on the pile built at rest (args: bodies, order as BM_StepOnlySettled's).
void BM_ColoredSolvePartsSettled(benchmark::State& state) {
  colored_solve_parts(state, pile(bodies_of(state), static_cast<int>(state.range(1)), true));
}

/// pgs-colored's pack and Δu⁰ alone (args: bodies, morton, evict): one-sweep solves of the settled
/// pile's problem from the builtin guess (the layout of a repeated contact set is kept, so the
/// pack runs on every solve, the ordering not), with `evict` MB of other data read before each
/// solve (0: none; 4: the core's L2, as the stages before the solve displace it; 64: beyond the
/// last-level cache of smaller machines). Counters ns_pack / ns_du0 / ns_sweep = thread CPU time
/// per contact of those parts (PgsColoredProfile).
void colored_pack(benchmark::State& state, const Pile& p) {
  dc::PgsColoredProfile prof;
  dc::PgsColoredDef def;
  def.profile = &prof;
  const auto solver = dc::make_pgs_colored(def);
  const dc::SolverOptions o = fixed_sweeps(1);
  const dc::LcpProblem& problem = p.world->problem();
  std::vector<double> evict(static_cast<std::size_t>(state.range(2)) << 17, 1.0);  // MB of doubles
  (void)solver->solve(problem, p.guess, o);
  prof = dc::PgsColoredProfile{};
  for (auto _ : state) {
    state.PauseTiming();
    touch_lines(evict);
    state.ResumeTiming();
    const dc::SolveResult r = solver->solve(problem, p.guess, o);
    benchmark::DoNotOptimize(r.lambda.data());
  }
  const double contacts = static_cast<double>(problem.constraints.size()) * static_cast<double>(state.iterations());
  state.counters["contacts"] = problem.constraints.size();
  state.counters["ns_pack"] = 1e9 * prof.pack / contacts;
  state.counters["ns_du0"] = 1e9 * prof.du0 / contacts;
  state.counters["ns_sweep"] = 1e9 * prof.sweeps / contacts;
  state.counters["compact"] = static_cast<double>(prof.compact_solves) / static_cast<double>(state.iterations());
}
void BM_ColoredPack(benchmark::State& state) { colored_pack(state, pile_of(state, 1)); }
/// BM_ColoredPack on the pile built at rest (args as BM_ColoredPack's; morton 1: the Morton
/// numbering, whose problem is ordered as the internal order's): about three contacts per body,
/// so the 40,000-body problem is past kStageFrom (pgs_colored_layout.hpp), the falling one not.
void BM_ColoredPackSettled(benchmark::State& state) {
  colored_pack(state, pile(bodies_of(state), static_cast<int>(state.range(1)), true));
}

void sizes(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "morton"});
  for (int n : {1000, 2500, 10000, 40000})
    for (int morton : {0, 1}) b->Args({n, morton});
}
void sizes_sweeps(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "sweeps", "morton"});
  for (int sweeps : {20, 1})
    for (int n : {1000, 2500, 10000, 40000})
      for (int morton : {0, 1}) b->Args({n, sweeps, morton});
}
/// sizes_sweeps with the internal order (morton = 2) and the default settings (morton = 3,
/// `internal_order = "auto"`) as further variants: whole steps only.
void sizes_sweeps_orders(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "sweeps", "morton"});
  for (int sweeps : {20, 1})
    for (int n : {1000, 2500, 5000, 10000, 20000, 40000})
      for (int morton : {0, 1, 2, 3}) b->Args({n, sweeps, morton});
}
/// The settled pile: 20 sweeps, every order.
void sizes_settled(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "sweeps", "morton"});
  for (int n : {1000, 2500, 5000, 10000, 20000, 40000})
    for (int morton : {0, 1, 2, 3}) b->Args({n, kSettleSweeps, morton});
}

/// 1,000, 10,000 and 40,000 bodies, 20 sweeps, every order.
void sizes_colored(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "sweeps", "morton"});
  for (int n : {1000, 10000, 40000})
    for (int morton : {0, 1, 2, 3}) b->Args({n, kSettleSweeps, morton});
}

void sizes_solvers(benchmark::internal::Benchmark* b) {
  b->ArgNames({"bodies", "colored", "morton"});
  for (int n : {1000, 10000, 40000})
    for (int colored : {0, 1})
      for (int morton : {0, 1, 2}) b->Args({n, colored, morton});
}

BENCHMARK(BM_Collide)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BroadPhase)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Assemble)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_WarmStart)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Solve)->Apply(sizes_sweeps)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Integrate)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Record)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ExternalOrder)
    ->ArgNames({"bodies", "source"})
    ->ArgsProduct({{1000, 10000, 40000}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Step)->Apply(sizes_sweeps_orders)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepOnly)->Apply(sizes_sweeps_orders)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepOnlySettled)->Apply(sizes_settled)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredStepOnly)->Apply(sizes_colored)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredStepOnlySettled)->Apply(sizes_colored)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepStages)->Apply(sizes_solvers)->Iterations(30)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepStagesSettled)
    ->ArgNames({"bodies", "morton"})
    ->ArgsProduct({{1000, 10000, 40000}, {0, 3}})
    ->Iterations(30)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadRate)->ArgName("MB")->RangeMultiplier(2)->Range(1, 256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredPack)
    ->ArgNames({"bodies", "morton", "evict"})
    ->ArgsProduct({{1000, 10000, 40000}, {3}, {0, 4}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredPackSettled)
    ->ArgNames({"bodies", "morton", "evict"})
    ->ArgsProduct({{1000, 10000, 40000}, {1}, {0, 4}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredSolveParts)
    ->ArgNames({"bodies", "morton"})
    ->ArgsProduct({{1000, 10000, 40000}, {0, 1}})
    ->Iterations(30)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ColoredSolvePartsSettled)
    ->ArgNames({"bodies", "morton"})
    ->ArgsProduct({{1000, 10000, 40000}, {0, 3}})
    ->Iterations(10)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
