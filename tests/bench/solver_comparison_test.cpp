// The bench's solver comparison (--solvers): every (solver, starter) pair solves every
// evaluated step, the comparison leaves the starters' own figures unchanged, each step's
// accuracy trace ends exactly where the target is first reached, and the summary has the
// keys docs/bench.md names.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bench/bench_fixtures.hpp"
#include "dc/bench/bench_report.hpp"
#include "dc/bench/bench_runner.hpp"
#include "dc/bench/solver_summary.hpp"
#include "dc/bench/provenance.hpp"
#include "dc/core/error.hpp"
#include "dc/io/h5.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

bench::BenchOptions comparison_run() {
  bench::BenchOptions o = test::small_pile();
  o.scene.time.steps = 70;
  o.seeds = {3, 4};
  o.warmstarts = {"zero", "builtin"};
  o.solvers = {SolverId{SolverKind::Pgs}, SolverId{SolverKind::Nncg}};
  o.max_sweeps = 2000;
  o.accuracy = 1e-6;
  return o;
}

TEST(SolverComparison, EveryPairSolvesEveryStepAndTheStartersFiguresStayTheSame) {
  const bench::BenchOptions o = comparison_run();
  const auto with = bench::run_bench(o, default_warm_starters());
  auto plain = o;
  plain.solvers.clear();
  const auto without = bench::run_bench(plain, default_warm_starters());
  EXPECT_TRUE(without.pairs.empty());
  ASSERT_EQ(with.pairs.size(), 4u);
  const char* order[4][2] = {{"pgs", "zero"}, {"pgs", "builtin"}, {"nncg", "zero"}, {"nncg", "builtin"}};
  const std::size_t n = with.starters[0].seed.size();
  ASSERT_GT(n, 20u);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& p = with.pairs[i];
    EXPECT_EQ(p.solver, order[i][0]);
    EXPECT_EQ(p.starter, order[i][1]);
    EXPECT_EQ(p.seed, with.starters[0].seed);
    EXPECT_EQ(p.iterations_to_accuracy.size(), n);
    EXPECT_EQ(p.ms_to_accuracy.size(), n);
    EXPECT_EQ(p.total_ms.size(), n);
    EXPECT_EQ(p.trace_offsets.size(), n + 1);
  }
  // The comparison neither changes the LCPs nor the starters' state.
  for (std::size_t s = 0; s < 2; ++s) {
    EXPECT_EQ(with.starters[s].sweeps_to_tol, without.starters[s].sweeps_to_tol);
    EXPECT_EQ(with.starters[s].initial_error, without.starters[s].initial_error);
  }
  const std::string json = bench::summary_json(without, bench::summarise(without), bench::collect_provenance());
  EXPECT_EQ(json.find("\"solvers\""), std::string::npos);
}

TEST(SolverComparison, TracesEndWhereTheTargetIsFirstReached) {
  const bench::BenchOptions o = comparison_run();
  const auto r = bench::run_bench(o, default_warm_starters());
  int reached = 0, missed = 0;
  for (std::size_t i = 0; i < r.pairs.size(); ++i) {
    const auto& p = r.pairs[i];
    const auto& starter = r.starters[i % r.starters.size()];
    for (std::size_t k = 0; k < p.seed.size(); ++k) {
      const std::size_t a = p.trace_offsets[k], b = p.trace_offsets[k + 1];
      ASSERT_LT(a, b);
      EXPECT_EQ(p.trace_ms[a], starter.warmstart_ms[k]) << "the trace starts at λ⁰, when the warm start is done";
      EXPECT_GT(p.weight_scale[k], 0.0);
      for (std::size_t t = a + 1; t < b; ++t) EXPECT_GE(p.trace_ms[t], p.trace_ms[t - 1]) << p.solver << "+" << p.starter;
      // Every point before the last is above the target; the last is at it exactly when reached.
      for (std::size_t t = a; t + 1 < b; ++t) EXPECT_GT(p.trace_accuracy[t], o.accuracy);
      EXPECT_EQ(p.final_accuracy[k], p.trace_accuracy[b - 1]);
      if (p.iterations_to_accuracy[k] >= 0) {
        ++reached;
        EXPECT_LE(p.trace_accuracy[b - 1], o.accuracy);
        EXPECT_LE(p.iterations_to_accuracy[k], o.max_sweeps);
        EXPECT_GE(p.ms_to_accuracy[k], p.trace_ms[a]);
      } else {
        ++missed;
        EXPECT_GT(p.trace_accuracy[b - 1], o.accuracy);
      }
    }
  }
  EXPECT_GT(reached, 0);
  (void)missed;
}

TEST(SolverComparison, SummaryHasTheFourFiguresPerPairWithIntervals) {
  const auto r = bench::run_bench(comparison_run(), default_warm_starters());
  const auto s = bench::summarise_solver_pairs(r);
  ASSERT_EQ(s.size(), 4u);
  for (const auto& x : s) {
    EXPECT_GE(x.reached_share.estimate, 0.0);
    EXPECT_LE(x.reached_share.estimate, 1.0);
    for (const bench::Interval& v : {x.reached_share, x.ms_to_accuracy, x.iterations_to_accuracy, x.total_ms}) {
      EXPECT_LE(v.lo, v.estimate);
      EXPECT_GE(v.hi, v.estimate);
    }
  }
  // pgs+builtin against itself: total ratio 1 exactly, and its interval holds 1.
  EXPECT_EQ(s[1].solver, "pgs");
  EXPECT_EQ(s[1].starter, "builtin");
  EXPECT_EQ(s[1].total_ratio.estimate, 1.0);
  EXPECT_TRUE(s[1].total_ratio.contains(1.0));
  const std::string json = bench::summary_json(r, bench::summarise(r), bench::collect_provenance());
  for (const char* key : {"\"solvers\"", "\"nncg\"", "\"reached_share\"", "\"median_ms_to_accuracy\"",
                          "\"median_iterations_to_accuracy\"", "\"median_total_ms\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
}

TEST(SolverComparison, NewtonSolversReportTheirFactorisationsAndProxNewtonItsPasses) {
  auto o = comparison_run();
  o.scene.time.steps = 40;
  o.seeds = {3};
  o.warmstarts = {"builtin"};
  o.solvers = {SolverId{SolverKind::Pgs}, SolverId{SolverKind::NewtonSparse}, SolverId{SolverKind::ProxNewton}};
  const auto r = bench::run_bench(o, default_warm_starters());
  ASSERT_EQ(r.pairs.size(), 3u);
  int solved = 0;
  for (std::size_t k = 0; k < r.pairs[0].seed.size(); ++k) {
    EXPECT_EQ(r.pairs[0].factorizations[k], -1) << "pgs does not factorise";
    EXPECT_EQ(r.pairs[0].outer_passes[k], -1);
    EXPECT_EQ(r.pairs[1].outer_passes[k], -1) << "newton-sparse has no outer passes";
    for (std::size_t i : {1u, 2u}) {
      const auto& p = r.pairs[i];
      // A solve that took Newton iterations factorised at least once; none when λ⁰ was at R,
      // nor when prox-newton's lead stage (nncg sweeps, before any pass) reached the target.
      if (p.iterations_to_accuracy[k] > 0) {
        if (i == 2 && p.outer_passes[k] == 0)
          EXPECT_EQ(p.factorizations[k], 0) << p.solver << " step " << k;
        else
          EXPECT_GE(p.factorizations[k], 1) << p.solver << " step " << k;
        ++solved;
      }
      if (p.iterations_to_accuracy[k] == 0) {
        EXPECT_EQ(p.factorizations[k], 0) << p.solver;
      }
      // The work to the first checkpoint at R is part of the whole traced solve's, and its
      // Newton iterations are among the iterations to R (prox-newton's lead sweeps come first).
      EXPECT_GE(p.factorizations_to_accuracy[k], 0) << p.solver << " step " << k;
      EXPECT_LE(p.factorizations_to_accuracy[k], p.factorizations[k]) << p.solver << " step " << k;
      EXPECT_GE(p.newton_to_accuracy[k], 0) << p.solver << " step " << k;
      if (p.iterations_to_accuracy[k] >= 0) {
        EXPECT_LE(p.newton_to_accuracy[k], p.iterations_to_accuracy[k]) << p.solver << " step " << k;
      }
      if (i == 1 && p.iterations_to_accuracy[k] >= 0) {
        EXPECT_EQ(p.newton_to_accuracy[k], p.iterations_to_accuracy[k]) << "newton-sparse step " << k;
      }
    }
    EXPECT_EQ(r.pairs[0].factorizations_to_accuracy[k], -1) << "pgs does not factorise";
    EXPECT_EQ(r.pairs[0].newton_to_accuracy[k], -1);
    EXPECT_GE(r.pairs[2].outer_passes[k], 0);
  }
  EXPECT_GT(solved, 0);
  const auto s = bench::summarise_solver_pairs(r);
  EXPECT_TRUE(std::isnan(s[0].factorizations.estimate));
  EXPECT_TRUE(std::isnan(s[1].outer_passes.estimate));
  for (std::size_t i : {1u, 2u}) {
    EXPECT_LE(s[i].factorizations.lo, s[i].factorizations.estimate);
    EXPECT_GE(s[i].factorizations.hi, s[i].factorizations.estimate);
    EXPECT_GE(s[i].p99_factorizations, s[i].factorizations.estimate);
  }
  EXPECT_TRUE(std::isfinite(s[2].outer_passes.estimate));
  const std::string json = bench::summary_json(r, bench::summarise(r), bench::collect_provenance());
  for (const char* key : {"\"median_factorizations\"", "\"p99_factorizations\"", "\"median_outer_passes\"",
                          "\"median_factorizations_to_accuracy\"", "\"p99_factorizations_to_accuracy\"",
                          "\"median_newton_to_accuracy\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  // results.h5 carries the same intervals under the figure names docs/bench.md lists.
  const test::TempDir dir;
  bench::write_results_h5(r, bench::collect_provenance(), dir / "results.h5");
  const H5File f = H5File::open_read(dir / "results.h5");
  const auto figures = f.read_strings("/solvers/interval_figures");
  ASSERT_EQ(figures.size(), 10u);
  const auto iv = f.read<double>("/solvers/intervals", {s.size(), figures.size(), 3});
  const auto at = [&](std::size_t pair, const std::string& figure, int k) {
    const auto j = static_cast<std::size_t>(std::find(figures.begin(), figures.end(), figure) - figures.begin());
    EXPECT_LT(j, figures.size()) << figure;
    return iv[(pair * figures.size() + j) * 3 + static_cast<std::size_t>(k)];
  };
  EXPECT_TRUE(std::isnan(at(0, "median_factorizations", 0))) << "pgs";
  EXPECT_TRUE(std::isnan(at(1, "median_outer_passes", 0))) << "newton-sparse";
  for (std::size_t i : {1u, 2u}) {
    EXPECT_EQ(at(i, "median_factorizations", 0), s[i].factorizations.estimate);
    EXPECT_EQ(at(i, "median_factorizations", 1), s[i].factorizations.lo);
    EXPECT_EQ(at(i, "median_factorizations", 2), s[i].factorizations.hi);
  }
  EXPECT_EQ(at(2, "median_outer_passes", 0), s[2].outer_passes.estimate);
  for (std::size_t i : {1u, 2u}) {
    EXPECT_EQ(at(i, "median_factorizations_to_accuracy", 0), s[i].factorizations_to_accuracy.estimate);
    EXPECT_EQ(at(i, "median_newton_to_accuracy", 0), s[i].newton_to_accuracy.estimate);
    EXPECT_LE(s[i].factorizations_to_accuracy.estimate, s[i].factorizations.estimate);
  }
  EXPECT_TRUE(std::isnan(at(0, "median_factorizations_to_accuracy", 0))) << "pgs";
}

TEST(SolverComparison, RefusesRolloutModeUnknownSolversAndABadTarget) {
  auto o = comparison_run();
  o.scene.time.steps = 5;
  o.mode = bench::Mode::Rollout;
  EXPECT_THROW(bench::run_bench(o, default_warm_starters()), ConfigError);
  o.mode = bench::Mode::Paired;
  EXPECT_THROW((void)SolverId::parse("no-such-solver"), ConfigError);  // names are read where given
  o.solvers = {SolverId{SolverKind::Pgs}};
  o.accuracy = 0.0;
  EXPECT_THROW(bench::run_bench(o, default_warm_starters()), ConfigError);
}

}  // namespace
}  // namespace dc
