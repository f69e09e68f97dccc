#pragma once
// The engine's stages on threads (World::step: collision, assembly, integration): `parts`
// independent jobs run on up to `threads` OpenMP threads. A job writes only its own outputs (a
// range of an array, or a buffer of its own that the caller merges in job order), so a result
// depends neither on the thread count nor on which thread ran which job. OpenMP's threads are
// those pgs-colored's solve runs on (one pool per calling thread), so the step's stages and its
// solve share one team.
#include <functional>

namespace dc {

/// Runs job(0), …, job(parts − 1): on `threads` threads when threads > 1 and parts > 1 (jobs
/// claimed one at a time as threads come free), else in order on the calling thread. An
/// exception of a job is rethrown on the calling thread once every job has ended.
void run_parts(int threads, int parts, const std::function<void(int)>& job);

/// Ends the calling thread's idle OpenMP threads (they would spin-wait, several milliseconds
/// after each parallel region under OpenMP's default wait policy, on cores other programs could
/// use); the next parallel region starts new ones.
void release_threads();

/// Jobs for `items` items of a stage on `threads` threads: 1 on one thread (the stage runs as one
/// job, with no merge), else `per_thread` jobs per thread, each of at least `min_items` items.
int parts_for(int threads, long items, int per_thread = 4, long min_items = 256);

/// First item of job p of `parts` over `items` items (job p has items [begin(p), begin(p + 1))).
inline long part_begin(long items, int parts, int p) { return items * p / parts; }

}  // namespace dc
