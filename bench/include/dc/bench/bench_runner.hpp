#pragma once
// The warm-start benchmark's runner (docs/design.md §6): runs every starter on every step of
// every evaluation scene, in paired or rollout mode, and returns what it measured
// (bench_results.hpp). It only runs: the summaries are bench_summary.hpp, the uncertainty
// bench_statistics.hpp, the files bench_report.hpp.
#include <functional>
#include <string>
#include <vector>

#include "dc/bench/bench_results.hpp"
#include "dc/warmstart/warm_starter.hpp"

namespace dc::bench {

/// Progress callback: (done, total, note).
using ProgressFn = std::function<void(long, long, const std::string&)>;

/// Runs the benchmark. Starters are built from `registry` (unknown names: ConfigError).
BenchResults run_bench(const BenchOptions& options, const WarmStarterRegistry& registry,
                       const ProgressFn& progress = {});

/// Log-spaced budgets 1, 2, 3, 5, 7, 10, 15, 20, 30, 50, 70, 100, … up to `sweeps` (included).
std::vector<int> default_budgets(int sweeps);

}  // namespace dc::bench
