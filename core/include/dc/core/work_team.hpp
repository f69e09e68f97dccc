#pragma once
// One persistent team of threads per calling thread, for the parallel parts of a World step and
// of pgs-colored's solve (set-up and sweeps), in place of a fork and join per parallel region.
// The calling thread is member 0 and works too; helpers 1, 2, … wait between runs (spin 10 µs,
// yield, then sleep on a futex: wake_word.hpp), so an idle team leaves its cores to other
// programs. No run waits for a helper to arrive: a helper that another program keeps off its
// core is simply not part of that run (its share is done by the members present), and the
// calling thread waits only for helpers that did join and are still working. A child process
// made by fork() inherits the team but not its threads: no helper ever joins there, so its runs
// are done by the calling thread alone (and glibc marks the parent's threads as ended, so the
// team's end joins them at once).
#include <atomic>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

#include "dc/core/wake_word.hpp"

namespace dc {

/// A non-owning reference to a callable `void(int)`: unlike std::function it never allocates
/// (a step's jobs capture more than std::function's small buffer holds). The callable must
/// outlive the call it is passed to.
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

/// Timing of one run of a team (WorkTeam::set_trace), on the steady clock [ns]: when the caller
/// published it, when helper 1 started its body (−1: it did not join), when member 0's body and
/// helper 1's body returned, and when the run ended; `woke`: the publish had to wake a sleeping
/// helper (a futex wake-up).
struct TeamRunTrace {
  std::int64_t publish = 0, helper_start = -1, caller_done = 0, helper_done = -1, end = 0;
  bool woke = false;
};

class WorkTeam {
 public:
  WorkTeam() = default;
  ~WorkTeam();
  WorkTeam(const WorkTeam&) = delete;
  WorkTeam& operator=(const WorkTeam&) = delete;

  /// Runs body(0) on the calling thread and body(m) on each helper m = 1 … threads − 1 that
  /// joins before body(0) has returned (a helper that comes later skips the run); returns once
  /// every member that joined has returned. The body must not assume any helper joins. The
  /// first exception of a member is rethrown on the calling thread.
  void gather(int threads, PartJob body);

  /// Runs job(0), …, job(parts − 1), each once, on up to `threads` members (jobs claimed one
  /// at a time as members come free, each member first from the front of its own contiguous
  /// block of the jobs, then from the back of the others'; serially in order when threads ≤ 1,
  /// parts ≤ 1 or inside a team's body). The first exception of a job is rethrown on the calling thread once every
  /// member has returned (a member stops claiming after a job of its own threw).
  void for_parts(int threads, int parts, PartJob job);

  /// True on a thread while it runs a body of some team's run (a nested run is serial).
  static bool inside();

  /// Appends a TeamRunTrace of every later threaded run to *trace (nullptr: none, the default).
  /// For measuring the hand-over; the vector must outlive the tracing.
  void set_trace(std::vector<TeamRunTrace>* trace) { trace_ = trace; }

 private:
  void grow(int helpers);
  void helper_loop(int member);
  void close(int member, std::int64_t run);

  /// A helper's gate: 2·run + 1 while it runs body of run `run`, 2·run + 2 once that run is
  /// closed to it (it returned, or never joined). Tags only grow.
  struct alignas(64) Gate {
    std::atomic<std::int64_t> tag{0};
  };

  std::vector<std::thread> helpers_;
  std::unique_ptr<Gate[]> gates_;  // one per helper (index member − 1), capacity kMaxHelpers
  static constexpr int kMaxHelpers = 63;
  alignas(64) std::atomic<std::int64_t> run_{0};  // the current run (0: none yet)
  PartJob* body_ = nullptr;            // the current run's body (read by a helper after joining)
  std::atomic<bool> stopping_{false};
  std::exception_ptr error_;
  std::mutex error_mutex_;
  WakeWord start_, done_;
  std::vector<TeamRunTrace>* trace_ = nullptr;
  TeamRunTrace current_;  // the run being traced (helper 1 writes its fields before closing)
};

/// The calling thread's team (its helpers start on first use and end with the thread).
WorkTeam& calling_thread_team();

/// First item of part p of `parts` even parts over `items` items (part p has items
/// [part_begin(p), part_begin(p + 1))): the split of for_parts' callers that cut an array.
inline long part_begin(long items, int parts, int p) { return items * p / parts; }

}  // namespace dc
