#pragma once
// Joining the results of bench runs over disjoint seed sets: the runner's parallel seeds
// (BenchOptions::jobs) and the MPI ranks of `deepcontact bench` both run each block of seeds
// into its own BenchResults and append them in seed order, so the joined results equal, field
// for field except the timings, those of one run over all the seeds.
#include "dc/bench/bench_results.hpp"

namespace dc::bench {

/// Appends every per-step entry of `from` (steps, starters' records, solver-comparison pairs) to
/// `to`. Both must come from the same options (same starters, budgets and solvers; IoError if the
/// starter or pair lists differ). The options, budgets, reference trajectory and wall time of
/// `to` are kept.
void append_results(BenchResults& to, const BenchResults& from);

}  // namespace dc::bench
