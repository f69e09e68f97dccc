#pragma once
// `deepcontact bench` across MPI ranks (docs/cluster.md): the seeds are split into
// contiguous blocks, one per rank (rank r gets block_of(seeds, r, K)); each rank runs
// run_bench on its block; rank 0 gathers the per-step records and concatenates them in rank
// order. run_bench appends everything seed by seed (both modes) and every seed's scene,
// starters and random streams depend on that seed alone, so the merged results equal the
// one-process run's in every field except the timings.
#include "dc/bench/bench_runner.hpp"

namespace dc::cli {

struct DistributedBenchTimes {
  double run_seconds = 0;     ///< this rank's run_bench
  double gather_seconds = 0;  ///< waiting for the slowest rank + packing, gathering, merging
};

/// As bench::run_bench, across world() (serial: run_bench itself). Rank 0 returns the merged
/// results (wall_seconds: from the start to after the merge); the other ranks return their
/// own block's results, which they should not report. `progress` is called on every rank for
/// its own block (each polls for stop signals there; only rank 0 should draw).
bench::BenchResults run_bench_across_ranks(const bench::BenchOptions& options, const WarmStarterRegistry& registry,
                                           const bench::ProgressFn& progress, DistributedBenchTimes* times = nullptr);

}  // namespace dc::cli
