// Parallel seeds (BenchOptions::jobs): the runs of several threads, joined in seed order, equal
// one thread's run in every figure but the timings — steps, sweeps to tol, residuals, λ errors,
// the solver comparison's iterations — and a failure in one thread reaches the caller.
#include <gtest/gtest.h>

#include <atomic>

#include "bench/bench_fixtures.hpp"
#include "dc/bench/bench_merge.hpp"
#include "dc/bench/bench_runner.hpp"
#include "dc/core/error.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc {
namespace {

bench::BenchOptions three_seeds() {
  bench::BenchOptions o = test::small_pile();
  o.scene.time.steps = 60;
  o.seeds = {5, 3, 4};  // not sorted: the joined results follow this order
  o.warmstarts = {"zero", "builtin", "sph-prev"};
  o.solvers = {SolverId{SolverKind::Pgs}, SolverId{SolverKind::Nncg}};
  o.max_sweeps = 1500;
  return o;
}

void expect_same_figures(const bench::BenchResults& a, const bench::BenchResults& b) {
  EXPECT_EQ(a.step_seed, b.step_seed);
  EXPECT_EQ(a.step_index, b.step_index);
  EXPECT_EQ(a.step_rows, b.step_rows);
  EXPECT_EQ(a.oracle_residual, b.oracle_residual);
  EXPECT_EQ(a.skipped_steps, b.skipped_steps);
  EXPECT_EQ(a.collide_ms.size(), b.collide_ms.size());
  ASSERT_EQ(a.starters.size(), b.starters.size());
  for (std::size_t i = 0; i < a.starters.size(); ++i) {
    const auto &x = a.starters[i], &y = b.starters[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.seed, y.seed);
    EXPECT_EQ(x.step, y.step);
    EXPECT_EQ(x.sweeps_to_tol, y.sweeps_to_tol) << x.name;
    EXPECT_EQ(x.sweeps_to_tol_high, y.sweeps_to_tol_high) << x.name;
    EXPECT_EQ(x.initial_error, y.initial_error) << x.name;
    EXPECT_EQ(x.residual, y.residual) << x.name;
    EXPECT_EQ(x.lambda_error, y.lambda_error) << x.name;
    EXPECT_EQ(x.energy_error, y.energy_error) << x.name;
    EXPECT_EQ(x.solve_ms.size(), y.solve_ms.size());
  }
  ASSERT_EQ(a.pairs.size(), b.pairs.size());
  for (std::size_t i = 0; i < a.pairs.size(); ++i) {
    EXPECT_EQ(a.pairs[i].seed, b.pairs[i].seed);
    EXPECT_EQ(a.pairs[i].iterations_to_accuracy, b.pairs[i].iterations_to_accuracy);
    EXPECT_EQ(a.pairs[i].final_accuracy, b.pairs[i].final_accuracy);
    EXPECT_EQ(a.pairs[i].trace_accuracy, b.pairs[i].trace_accuracy);
    EXPECT_EQ(a.pairs[i].trace_offsets, b.pairs[i].trace_offsets);
  }
  // The report's frame is the first listed seed's, whichever thread ran it.
  ASSERT_TRUE(a.reference && b.reference);
  EXPECT_EQ(a.reference_scene, b.reference_scene);
}

TEST(ParallelSeeds, TwoAndThreeThreadsGiveTheOneThreadFigures) {
  const auto registry = default_warm_starters();
  bench::BenchOptions o = three_seeds();
  const bench::BenchResults one = bench::run_bench(o, registry);
  ASSERT_EQ(one.step_seed.front(), 5u);
  for (const int jobs : {2, 3}) {
    o.jobs = jobs;
    std::atomic<long> calls{0};
    long last_total = 0;
    const bench::BenchResults many = bench::run_bench(o, registry, [&](long done, long total, const std::string&) {
      ++calls;
      EXPECT_LE(done, total);
      last_total = total;
    });
    SCOPED_TRACE(jobs);
    expect_same_figures(one, many);
    EXPECT_EQ(many.options.jobs, jobs);
    EXPECT_EQ(calls.load(), last_total);  // one call per evaluated step, counted across threads
  }
}

TEST(ParallelSeeds, AFailingSeedReachesTheCaller) {
  bench::BenchOptions o = three_seeds();
  o.solvers.clear();
  o.jobs = 2;
  o.warmstarts = {"zero", "no-such-starter"};
  EXPECT_THROW((void)bench::run_bench(o, default_warm_starters()), ConfigError);
  o.warmstarts = {"zero"};
  o.jobs = 0;
  EXPECT_THROW((void)bench::run_bench(o, default_warm_starters()), ConfigError);
}

TEST(ParallelSeeds, JoiningRefusesResultsOfOtherStarters) {
  bench::BenchResults a, b;
  a.starters.resize(2);
  b.starters.resize(1);
  EXPECT_THROW(bench::append_results(a, b), IoError);
  b.starters.resize(2);
  b.starters[1].name = "other";
  a.starters[1].name = "builtin";
  EXPECT_THROW(bench::append_results(a, b), IoError);
}

TEST(ParallelSeeds, JoiningShiftsTheTraceOffsets) {
  bench::BenchResults a, b;
  a.pairs.resize(1);
  b.pairs.resize(1);
  a.pairs[0].trace_offsets = {0, 2};
  a.pairs[0].trace_ms = {0.1, 0.2};
  a.pairs[0].trace_accuracy = {1.0, 0.5};
  b.pairs[0].trace_offsets = {0, 1, 3};
  b.pairs[0].trace_ms = {0.3, 0.4, 0.5};
  b.pairs[0].trace_accuracy = {0.9, 0.8, 0.7};
  bench::append_results(a, b);
  EXPECT_EQ(a.pairs[0].trace_offsets, (std::vector<std::size_t>{0, 2, 3, 5}));
  EXPECT_EQ(a.pairs[0].trace_accuracy, (std::vector<double>{1.0, 0.5, 0.9, 0.8, 0.7}));
}

}  // namespace
}  // namespace dc
