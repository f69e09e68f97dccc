#pragma once
// The engine's stages on threads (World::step: collision, assembly, integration): `parts`
// independent jobs run on up to `threads` members of the calling thread's team
// (dc/core/work_team.hpp). A job writes only its own outputs (a range of an array, or a buffer
// of its own that the caller merges in job order), so a result depends neither on the thread
// count nor on which thread ran which job. pgs-colored's solve runs on the same team, so one
// set of threads serves the whole step.
#include "dc/core/work_team.hpp"

namespace dc {

/// Runs job(0), …, job(parts − 1): on `threads` threads when threads > 1 and parts > 1 (jobs
/// claimed one at a time as threads come free; WorkTeam::for_parts), else in order on the
/// calling thread. An exception of a job is rethrown on the calling thread.
void run_parts(int threads, int parts, PartJob job);

/// Jobs for `items` items of a stage on `threads` threads: 1 on one thread (the stage runs as one
/// job, with no merge), else `per_thread` jobs per thread, each of at least `min_items` items.
int parts_for(int threads, long items, int per_thread = 4, long min_items = 256);

}  // namespace dc
