#pragma once
// The point summary of each starter of a bench run: the medians (and the quartiles of the
// sweeps) over its evaluated steps that the table, summary.json and the size sweep show
// (docs/bench.md). Their uncertainty is bench_statistics.hpp.
#include <string>
#include <vector>

#include "dc/bench/bench_results.hpp"
#include "dc/bench/quantiles.hpp"

namespace dc::bench {

struct StarterSummary {
  std::string name;
  bool uses_oracle = false;
  double median_sweeps_to_tol = 0;   ///< never-converged steps count as `sweeps` + 1 (∞)
  Quartiles sweeps_to_tol;
  double unconverged_share = 0;      ///< share of steps that never reach tol
  double warmstart_ms = 0;           ///< median per step
  double oracle_ms = 0;              ///< median per step (own oracle, or the shared one if uses_oracle)
  double solve_ms = 0;               ///< median per step
  double total_ms = 0;               ///< median of (warmstart + solve) per step
  double ns_per_row_sweep = 0;       ///< median
  double initial_error = 0;          ///< median ‖λ⁰ − λ*‖∞ [N]
  double residual_at_budget = 0;     ///< median natural-map residual after `budget` sweeps [N]
  double residual_at_cap = 0;        ///< median natural-map residual after `sweeps` sweeps [N]
  double median_sweeps_high = 0;     ///< with max_sweeps: median sweeps to tol, never = max_sweeps + 1
  double unconverged_share_high = 0; ///< with max_sweeps: share never reaching tol within it
};

/// One summary per starter, in the results' order. The medians are quartiles(…).median
/// (quantiles.hpp).
std::vector<StarterSummary> summarise(const BenchResults& r);

}  // namespace dc::bench
