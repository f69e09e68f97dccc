// Google Benchmark of "nncg" (PGS sweeps with nonlinear conjugate-gradient momentum,
// lcp/src/solvers/nncg.cpp) against "pgs" on the same problems, in one process:
//  BM_SweepCost/<solver>  the 12 × 40 deep_pile of tests/lcp/solver_test_problems.hpp,
//                         200 sweeps from λ⁰ = 0, tolerance 0: ns_per_row_sweep = CPU time /
//                         (rows · sweeps); nncg's iteration is a pgs sweep plus O(rows + bodies).
//  BM_ToTolerance/<solver>/<layers>  12-wide piles of 10, 20, 40, 80 layers from λ⁰ = 0 until
//                         θ ≤ 1e-3 N (cap 100,000 sweeps): CPU time per solve and `sweeps`.
//   build/bin/micro_nncg --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include "../../tests/lcp/solver_test_problems.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace {

constexpr int kWidth = 12;

void BM_SweepCost(benchmark::State& state, const char* solver_name) {
  const dc::LcpProblem p = dc::test::deep_pile(kWidth, 40, 0.5);
  const auto solver = dc::make_solver(solver_name);
  dc::SolverOptions o;
  o.max_sweeps = 200;
  o.record_theta = false;
  for (auto _ : state) {
    const dc::SolveResult r = solver->solve(p, {}, o);
    benchmark::DoNotOptimize(r.lambda.data());
  }
  state.counters["rows"] = p.rows();
  state.counters["ns_per_row_sweep"] = benchmark::Counter(
      1e-9 * static_cast<double>(p.rows()) * o.max_sweeps * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_ToTolerance(benchmark::State& state, const char* solver_name) {
  const dc::LcpProblem p = dc::test::deep_pile(kWidth, static_cast<int>(state.range(0)), 0.5);
  const auto solver = dc::make_solver(solver_name);
  dc::SolverOptions o;
  o.max_sweeps = 100000;
  o.tolerance = 1e-3;
  o.record_theta = false;
  int sweeps = 0;
  for (auto _ : state) {
    const dc::SolveResult r = solver->solve(p, {}, o);
    sweeps = r.sweeps;
    benchmark::DoNotOptimize(r.lambda.data());
  }
  state.counters["rows"] = p.rows();
  state.counters["sweeps"] = sweeps;
}

BENCHMARK_CAPTURE(BM_SweepCost, pgs, "pgs")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_SweepCost, nncg, "nncg")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_ToTolerance, pgs, "pgs")->Arg(10)->Arg(20)->Arg(40)->Arg(80)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ToTolerance, nncg, "nncg")->Arg(10)->Arg(20)->Arg(40)->Arg(80)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
