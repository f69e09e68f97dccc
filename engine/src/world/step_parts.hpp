#pragma once
// The engine's stages on threads (World::step: collision, assembly, integration): `parts`
// independent jobs run on up to `threads` OpenMP threads. A job writes only its own outputs (a
// range of an array, or a buffer of its own that the caller merges in job order), so a result
// depends neither on the thread count nor on which thread ran which job. OpenMP's threads are
// those pgs-colored's solve runs on (one pool per calling thread), so the step's stages and its
// solve share one team.
#include <type_traits>
#include <utility>

namespace dc {

/// A non-owning reference to a callable `void(int)`: unlike std::function it never allocates
/// (a step's jobs capture more than std::function's small buffer holds, and the step is meant
/// to allocate nothing at steady state). The callable must outlive the call it is passed to.
class PartJob {
 public:
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, PartJob>>>
  PartJob(F&& f) noexcept  // NOLINT(google-explicit-constructor): passed as a lambda
      : object_(const_cast<void*>(static_cast<const void*>(&f))),
        call_([](void* o, int p) { (*static_cast<std::remove_reference_t<F>*>(o))(p); }) {}
  void operator()(int p) const { call_(object_, p); }

 private:
  void* object_;
  void (*call_)(void*, int);
};

/// Runs job(0), …, job(parts − 1): on `threads` threads when threads > 1 and parts > 1 (jobs
/// claimed one at a time as threads come free), else in order on the calling thread. An
/// exception of a job is rethrown on the calling thread once every job has ended.
void run_parts(int threads, int parts, PartJob job);

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
