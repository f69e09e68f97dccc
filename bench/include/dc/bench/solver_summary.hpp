#pragma once
// The solver comparison's summary (docs/bench.md "Solver comparison"): per (solver, starter)
// pair the share of steps reaching the accuracy target R, the medians of time and iterations
// to R and of the total time to the run's θ tolerance, with hierarchical bootstrap intervals
// (bench_statistics.hpp: seeds, then steps within a seed; one draw for all pairs, which solved
// identical LCPs), and the ratios to pgs+builtin's median total time. The summary.json object
// "solvers", the report.md table and results.h5's /solvers group are written from it.
#include <limits>
#include <string>
#include <vector>

#include "dc/bench/bench_results.hpp"
#include "dc/bench/bench_statistics.hpp"

namespace dc {
class JsonWriter;
}

namespace dc::bench {

struct SolverPairSummary {
  std::string solver, starter;
  std::size_t steps = 0;
  /// Estimates with intervals. A step that never reaches R counts at the cap: its iterations
  /// as the cap (max_sweeps, else sweeps), its time as the whole run's.
  Interval reached_share, ms_to_accuracy, iterations_to_accuracy, total_ms;
  /// median ms to R / pgs+builtin's median total ms, and median total ms / the same (NaN when
  /// that pair did not run).
  Interval ms_to_accuracy_ratio, total_ratio;
  /// Work of the trace's solves (SolverPairRecord::factorizations, outer_passes): medians with
  /// intervals and the 99th percentile of factorisations; NaN for a solver that does not count it.
  Interval factorizations, outer_passes;
  double p99_factorizations = std::numeric_limits<double>::quiet_NaN();
  /// The same solves' work up to the first checkpoint at R (SolverPairRecord::
  /// factorizations_to_accuracy, newton_to_accuracy), as ms_to_accuracy: medians with intervals
  /// and the 99th percentile of factorisations; NaN for a solver that does not count it.
  Interval factorizations_to_accuracy, newton_to_accuracy;
  double p99_factorizations_to_accuracy = std::numeric_limits<double>::quiet_NaN();
};

/// One summary per pair, in the order of BenchResults::pairs (empty without --solvers).
std::vector<SolverPairSummary> summarise_solver_pairs(const BenchResults& r, const BootstrapDef& def = {});

/// The "solvers" object of summary.json: {SOLVER: {STARTER: {"reached_share",
/// "median_ms_to_accuracy", "median_iterations_to_accuracy", "median_total_ms"}}}, and for
/// solvers that count them "median_factorizations", "p99_factorizations", "median_outer_passes"
/// (the whole traced solve, to R/100), "median_factorizations_to_accuracy",
/// "p99_factorizations_to_accuracy", "median_newton_to_accuracy" (up to the first checkpoint at R).
void solver_pairs_json(JsonWriter& j, const std::vector<SolverPairSummary>& s);

/// report.md's "Solver comparison" section: what was measured, and the table with intervals.
std::string solver_pairs_markdown(const BenchResults& r, const std::vector<SolverPairSummary>& s);

}  // namespace dc::bench
