// step_threads: whole steps of the scaled seed pile with pgs-colored on 1 and 2 threads,
// alternated inside each round, timed per step by the wall clock and by the CPU time of the
// stepping thread (the second is what a busy machine disturbs least). Reported per body count
// and thread count: medians over all timed steps (and the wall clock's mean, which counts rare
// slow steps), the wall time of each stage (StepProfile medians), the heap allocations per
// timed step (of the whole process, helpers included: counting_malloc.hpp), the CPU model and
// the load average before and after.
//
//   build/bin/step_threads [--n 1000,10000] [--threads 1,2] [--steps 40] [--rounds 5]
//                          [--sweeps 20] [--min-batches -1] [--load 0] [--profile] [--handover]
//                          [--trace-steps] [--interleave] [--at-rest]
//
// --load K runs K competitor processes (busy_load.hpp: plain spinning arithmetic at this
// program's nice level) through the rounds of each body count, warm-up included, so that 1 and
// 2 threads are compared on a machine whose cores are taken: `--load 2` on 2 cores is the case
// where a second thread can only pay if it never leaves member 0 waiting for a descheduled
// helper. The header line gives K; each body count's "competitors" line the mean share of a
// core each competitor got (what the machine's other programs left them shows there too).
// --interleave steps the thread counts' Worlds in turn, step by step (the order alternating by
// step), instead of one after the other in each round: on a busy machine each pair of steps
// then meets the same background, where round-by-round alternation leaves whole rounds to the
// luck of the scheduler; each step then finds the caches holding the other World's data.
// --trace-steps prints each timed step of the series on more than one thread: threaded (a
// helper's CPU time above kHelped of the stepping thread's) or serial, its wall and thread CPU
// time and its stages' wall times: the pacer's probes, the steps that stalled and the serial
// steps after a threaded one (which find the step's data in the other core's cache). The
// summary gives the serial steps (no helper worked) apart as well: their count and medians.
// --min-batches sets PgsColoredDef::min_batches_per_thread (-1: the solver's default; 0 threads
// every problem and every large step: no pacing, LcpSolver::threads_forced). --profile adds the
// solve's phases (PgsColoredProfile: CPU time of the stepping thread per solve). The pile and
// its settling are those of micro_step (150 steps of pgs); --at-rest takes micro_step's pile packed
// on the floor (settled_pile.hpp), where nearly every contact carries load and the sweeps weigh
// most, instead of the falling one (most rows free at 10,000 bodies). --handover traces the team's runs
// (WorkTeam::set_trace) and prints, per stage of the threaded steps: runs per step, how many
// helper 1 joined, how many had to wake it from its futex sleep, and the medians of the
// hand-over (publish to the helper's start), of member 0's body and of its wait after it, the
// time per step outside runs (serial on member 0) and helper 1's time in bodies. The steps a
// helper worked in are also reported apart (wall, stages): the pacing mixes serial steps in.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "dc/core/work_team.hpp"
#include "dc/engine/world.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "busy_load.hpp"
#include "counting_malloc.hpp"
#include "fixed_sweeps.hpp"
#include "settled_pile.hpp"

namespace {

double clock_s(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + ", " + b + ", " + c;
}

std::vector<int> parse_ints(const std::string& s) {
  std::vector<int> v;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) v.push_back(std::stoi(item));
  return v;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

using dc::bench_micro::fixed_sweeps;

/// micro_step's scaled seed pile of n circles after 150 steps of pgs: falling (most rows free at
/// 10,000 bodies), or with `at_rest` the same bodies packed on the floor (settled_pile.hpp,
/// shuffled numbering as generated bodies have), where nearly every contact carries load.
dc::World settled_pile(int n, const std::string& order, bool at_rest) {
  dc::WorldDef def = at_rest ? dc::bench_micro::packed_pile(n, false) : dc::stress::scaled_seed_pile(n);
  if (!order.empty()) def.bodies.internal_order = dc::parse_internal_order(order, "--internal-order");
  def.solver.sweeps = 20;
  dc::World w(def);
  const auto pgs = dc::make_solver("pgs");
  const dc::SolverOptions o = fixed_sweeps(20);
  for (int k = 0; k < 150; ++k) w.step(*pgs, o, dc::World::WarmStart::PreviousLambda);
  return w;
}

struct Series {
  int threads = 1;
  std::unique_ptr<dc::LcpSolver> solver;
  std::vector<double> wall_ms, cpu_ms;
  std::vector<double> stage_ms[5];  // collide, assemble, warm start, solve, integrate
  /// The steps a helper worked in (process CPU above the stepping thread's by more than
  /// kHelped of it): their wall time and stages, apart from the serial steps of the pacing.
  std::vector<double> helped_wall_ms, helped_stage_ms[5];
  std::vector<double> serial_wall_ms, serial_cpu_ms;  // the other steps (no helper worked): wall and thread CPU
  long allocations = 0;             // over the timed steps
  std::unique_ptr<dc::PgsColoredProfile> profile = std::make_unique<dc::PgsColoredProfile>();
};

/// The team's runs of the traced steps, attributed to stages by their publish time.
struct Handover {
  int steps = 0;
  std::vector<dc::TeamRunTrace> runs[5];
  std::vector<double> outside_ms[6];  // per stage and the whole step: wall time outside team runs
  std::vector<double> helper_ms[6];   // per stage and the whole step: helper 1's time in bodies
  int threaded_steps = 0;             // steps with at least one run of the team
  /// The runs traced since `from` of one step that began at `start` [ns] with profile p.
  void add(const std::vector<dc::TeamRunTrace>& trace, size_t from, std::int64_t start, const dc::StepProfile& p) {
    const double ms[5] = {p.collide_ms, p.assemble_ms, p.warmstart_ms, p.solve_ms, p.integrate_ms};
    ++steps;
    double outside[6] = {ms[0], ms[1], ms[2], ms[3], ms[4], p.total_ms()};
    double helper[6] = {0, 0, 0, 0, 0, 0};
    threaded_steps += trace.size() > from ? 1 : 0;
    for (size_t i = from; i < trace.size(); ++i) {
      double at = 1e-6 * static_cast<double>(trace[i].publish - start), edge = 0.0;
      int k = 0;
      while (k < 4 && at > (edge += ms[k])) ++k;
      runs[k].push_back(trace[i]);
      const double in_run = 1e-6 * static_cast<double>(trace[i].end - trace[i].publish);
      outside[k] -= in_run;
      outside[5] -= in_run;
      if (trace[i].helper_start >= 0) {
        const double busy = 1e-6 * static_cast<double>(trace[i].helper_done - trace[i].helper_start);
        helper[k] += busy;
        helper[5] += busy;
      }
    }
    for (int k = 0; k < 6; ++k) {
      outside_ms[k].push_back(outside[k]);
      helper_ms[k].push_back(helper[k]);
    }
  }
  void print(int n, int threads) const {
    static const char* names[5] = {"collide", "assemble", "warm start", "solve", "integrate"};
    std::printf("#   hand-over, %d bodies, %d threads, per stage: runs/step, joined %%, futex wake %%, "
                "median µs: publish→helper start, member 0 body, member 0 wait after, helper body; "
                "median ms/step outside runs, mean ms/step of helper 1 in bodies\n", n, threads);
    for (int k = 0; k < 5; ++k) {
      const auto& v = runs[k];
      std::vector<double> lat, body, wait, hbody;
      int joined = 0, woke = 0;
      for (const auto& r : v) {
        if (r.helper_start >= 0) {
          ++joined;
          lat.push_back(1e-3 * static_cast<double>(r.helper_start - r.publish));
          hbody.push_back(1e-3 * static_cast<double>(r.helper_done - r.helper_start));
        }
        woke += r.woke ? 1 : 0;
        body.push_back(1e-3 * static_cast<double>(r.caller_done - r.publish));
        wait.push_back(1e-3 * static_cast<double>(r.end - r.caller_done));
      }
      const double nr = std::max<double>(1.0, static_cast<double>(v.size()));
      std::printf("#     %-10s %5.1f  %5.1f%%  %5.1f%%  %7.1f  %7.1f  %7.1f  %7.1f  %.3f  %.3f\n", names[k],
                  static_cast<double>(v.size()) / std::max(1, steps), 100.0 * joined / nr, 100.0 * woke / nr,
                  median(lat), median(body), median(wait), median(hbody), median(outside_ms[k]), mean(helper_ms[k]));
    }
    std::printf("#     whole step: outside runs %.3f ms (median), helper 1 in bodies %.3f ms (mean); "
                "steps with team runs %d of %d\n", median(outside_ms[5]), mean(helper_ms[5]), threaded_steps, steps);
  }
};

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

constexpr double kHelped = 0.02;  // a helper's CPU share of a step that marks it threaded

void add_stages(Series& s, const dc::StepProfile& p, bool helped, double wall_ms) {
  const double ms[5] = {p.collide_ms, p.assemble_ms, p.warmstart_ms, p.solve_ms, p.integrate_ms};
  for (int i = 0; i < 5; ++i) s.stage_ms[i].push_back(ms[i]);
  if (!helped) return;
  s.helped_wall_ms.push_back(wall_ms);
  for (int i = 0; i < 5; ++i) s.helped_stage_ms[i].push_back(ms[i]);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Whole pgs-colored steps on 1 and 2 threads, alternated"};
  std::string ns = "1000,10000", ts = "1,2";
  int steps = 40, rounds = 5, sweeps = 20, min_batches = -1, load = 0;
  bool profile = false, handover = false, trace_steps = false, interleave = false, at_rest = false;
  std::string internal_order;
  app.add_option("--n", ns, "body counts, comma-separated");
  app.add_option("--threads", ts, "thread counts, comma-separated");
  app.add_option("--steps", steps, "timed steps per configuration and round");
  app.add_option("--rounds", rounds, "rounds (the configurations alternate inside each)");
  app.add_option("--sweeps", sweeps, "sweeps per step (tolerance 0)");
  app.add_option("--min-batches", min_batches, "PgsColoredDef::min_batches_per_thread (-1: default)");
  app.add_option("--internal-order", internal_order, "[bodies] internal_order of the pile (auto, morton, none; "
                 "default: the scene's)");
  app.add_option("--load", load, "competitor processes spinning through the rounds (0: none)")
      ->check(CLI::Range(0, 64));
  app.add_flag("--at-rest", at_rest, "the pile packed on the floor and settled (micro_step's BM_StepOnlySettled "
               "pile) instead of the falling one");
  app.add_flag("--profile", profile, "print the solve's phases (thread CPU ms per solve, all rounds)");
  app.add_flag("--interleave", interleave, "alternate the thread counts step by step (each on its own World) "
               "instead of round by round");
  app.add_flag("--trace-steps", trace_steps, "print every timed step of the threaded series (threaded or serial: "
               "a helper's CPU share; wall and thread CPU ms)");
  app.add_flag("--handover", handover, "trace the team's runs: the hand-over per stage of the threaded steps");
  CLI11_PARSE(app, argc, argv);
  std::vector<dc::TeamRunTrace> trace;
  const dc::SolverOptions o = fixed_sweeps(sweeps);
  std::printf("# step_threads: pgs-colored, %s pile, %d sweeps, %d steps x %d rounds; %d competitor processes (--load); "
              "CPU %s, %ld online; load %s\n", at_rest ? "packed (at rest)" : "falling", sweeps, steps, rounds, load, dc::bench::cpu_model().c_str(),
              sysconf(_SC_NPROCESSORS_ONLN), load_average().c_str());
  std::printf("| bodies | threads | wall ms/step | wall mean | thread CPU ms/step | process CPU ms/step | "
              "wall 1/T |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const int n : parse_ints(ns)) {
    const dc::World start = settled_pile(n, internal_order, at_rest);
    std::vector<Series> series;
    std::vector<double> process_ms;
    for (const int t : parse_ints(ts)) {
      dc::PgsColoredDef def;
      def.threads = t;
      if (min_batches >= 0) def.min_batches_per_thread = min_batches;
      Series s;
      s.threads = t;
      if (profile) def.profile = s.profile.get();
      s.solver = dc::make_pgs_colored(def);
      series.push_back(std::move(s));
    }
    std::vector<std::vector<double>> proc(series.size());
    std::vector<Handover> handovers(series.size());
    dc::bench::BusyLoad competitors;
    competitors.start(load);
    // One timed step of series si on world w in round r (r < 0: warm-up, not recorded).
    auto one_step = [&](size_t si, dc::World& w, int r, int k) {
      Series& s = series[si];
      const bool traced = handover && r >= 0 && s.threads > 1;
      if (traced) dc::calling_thread_team().set_trace(&trace);
      const size_t from = trace.size();
      const std::int64_t start_ns = steady_ns();
      const double w0 = clock_s(CLOCK_MONOTONIC), c0 = clock_s(CLOCK_THREAD_CPUTIME_ID),
                   p0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
      const long a0 = dc::bench::AllocationCounter::count();
      dc::bench::AllocationCounter::start();
      const dc::StepReport rep = w.step(*s.solver, o, dc::World::WarmStart::PreviousLambda);
      dc::bench::AllocationCounter::stop();
      if (r >= 0) s.allocations += dc::bench::AllocationCounter::count() - a0;
      dc::calling_thread_team().set_trace(nullptr);
      if (traced) handovers[si].add(trace, from, start_ns, rep.profile);
      if (r < 0) return;
      s.wall_ms.push_back(1e3 * (clock_s(CLOCK_MONOTONIC) - w0));
      s.cpu_ms.push_back(1e3 * (clock_s(CLOCK_THREAD_CPUTIME_ID) - c0));
      proc[si].push_back(1e3 * (clock_s(CLOCK_PROCESS_CPUTIME_ID) - p0));
      const bool helped = proc[si].back() > (1 + kHelped) * s.cpu_ms.back();
      add_stages(s, rep.profile, helped, s.wall_ms.back());
      if (!helped) {
        s.serial_wall_ms.push_back(s.wall_ms.back());
        s.serial_cpu_ms.push_back(s.cpu_ms.back());
      }
      if (trace_steps && s.threads > 1)
        std::printf("# step %d bodies, %d threads, round %d, step %d: %s, wall %.3f ms, thread CPU %.3f ms; stages "
                    "%.3f, %.3f, %.3f, %.3f, %.3f\n", n, s.threads, r, k, helped ? "threaded" : "serial",
                    s.wall_ms.back(), s.cpu_ms.back(), rep.profile.collide_ms, rep.profile.assemble_ms,
                    rep.profile.warmstart_ms, rep.profile.solve_ms, rep.profile.integrate_ms);
    };
    const size_t configs = series.size();
    for (int r = -1; r < rounds; ++r) {  // round −1: warm-up, not timed
      std::vector<std::unique_ptr<dc::World>> worlds(configs);
      if (interleave) {  // every series its own World, stepped in turn (the order alternates by step)
        for (auto& w : worlds) w = std::make_unique<dc::World>(start);
        for (int k = 0; k < steps; ++k)
          for (size_t j = 0; j < configs; ++j) {
            const size_t si = (r + k) % 2 != 0 ? configs - 1 - j : j;
            one_step(si, *worlds[si], r, k);
          }
        continue;
      }
      for (size_t j = 0; j < configs; ++j) {
        const size_t si = r % 2 != 0 ? configs - 1 - j : j;  // alternate the order by round
        worlds[si] = std::make_unique<dc::World>(start);
        for (int k = 0; k < steps; ++k) one_step(si, *worlds[si], r, k);
      }
    }
    const double share = competitors.stop();
    const double base = median(series.front().wall_ms);
    for (size_t j = 0; j < series.size(); ++j) {
      const double wall = median(series[j].wall_ms);
      std::printf("| %d | %d | %.3f | %.3f | %.3f | %.3f | %.2f× |\n", n, series[j].threads, wall,
                  mean(series[j].wall_ms), median(series[j].cpu_ms), median(proc[j]), base / wall);
    }
    if (load > 0)
      std::printf("#   %d bodies: competitors: %d, each got %.2f of a core (mean over the rounds); load %s\n", n, load,
                  share, load_average().c_str());
    std::printf("#   stage wall ms/step (medians): collide, assemble, warm start, solve, integrate\n");
    for (const Series& s : series)
      std::printf("#   %d bodies, %d threads: %.3f, %.3f, %.3f, %.3f, %.3f\n", n, s.threads, median(s.stage_ms[0]),
                  median(s.stage_ms[1]), median(s.stage_ms[2]), median(s.stage_ms[3]), median(s.stage_ms[4]));
    std::printf("#   steps a helper worked in (process CPU > %.2f x thread CPU): count, wall ms/step and stages "
                "(medians), wall ratio to the first thread count's median\n", 1 + kHelped);
    for (const Series& s : series) {
      const auto& h = s.helped_stage_ms;
      std::printf("#   %d bodies, %d threads: %zu of %zu, %.3f; %.3f, %.3f, %.3f, %.3f, %.3f; %.2fx\n", n, s.threads,
                  s.helped_wall_ms.size(), s.wall_ms.size(), median(s.helped_wall_ms), median(h[0]), median(h[1]),
                  median(h[2]), median(h[3]), median(h[4]),
                  s.helped_wall_ms.empty() ? 0.0 : base / median(s.helped_wall_ms));
    }
    std::printf("#   serial steps (no helper worked): count, wall ms/step and thread CPU ms/step (medians)\n");
    for (const Series& s : series)
      std::printf("#   %d bodies, %d threads: %zu of %zu, %.3f, %.3f\n", n, s.threads, s.serial_wall_ms.size(),
                  s.wall_ms.size(), median(s.serial_wall_ms), median(s.serial_cpu_ms));
    std::printf("#   heap allocations per timed step (the report's λ is one while the rows change)\n");
    for (const Series& s : series)
      std::printf("#   %d bodies, %d threads: %.2f\n", n, s.threads,
                  static_cast<double>(s.allocations) / std::max<double>(1.0, static_cast<double>(s.wall_ms.size())));
    for (size_t j = 0; j < series.size(); ++j)
      if (handover && series[j].threads > 1) handovers[j].print(n, series[j].threads);
    if (!profile) continue;
    std::printf("#   solve phases, thread CPU ms per solve: checks, coloring, ordering, du0, pack, sweeps, "
                "unpermute, residual\n");
    for (const Series& s : series) {
      const dc::PgsColoredProfile& q = *s.profile;
      const double k = q.solves > 0 ? 1e3 / static_cast<double>(q.solves) : 0.0;
      std::printf("#   %d bodies, %d threads: %.3f, %.3f, %.3f, %.3f, %.3f, %.3f, %.3f, %.3f\n", n, s.threads,
                  k * q.checks, k * q.coloring, k * q.ordering, k * q.du0, k * q.pack, k * q.sweeps, k * q.unpermute,
                  k * q.residual);
    }
  }
  std::printf("# load after: %s\n", load_average().c_str());
  return 0;
}
