// ThreadPacer on stub run times (no clock): the runs' costs per unit of work are scripted as a
// busy machine makes them (a serial run now and then descheduled for a time slice; threaded
// runs that stall unless both members happen to run) and as a free one does, and the tests
// check which runs the pacer threads.
#include <gtest/gtest.h>

#include <functional>

#include "dc/core/thread_pacer.hpp"

namespace dc {
namespace {

/// Runs `runs` runs of one unit of work through `pacer`; cost(threaded, k, after_serial) gives
/// run k's time (after_serial: the run before it was serial, i.e. a threaded run is a probe or
/// the first threaded run). Returns how many runs were threaded.
int threaded_runs(ThreadPacer& pacer, int runs, const std::function<double(bool, int, bool)>& cost) {
  int threaded_count = 0;
  bool last_serial = true;
  for (int k = 0; k < runs; ++k) {
    const bool threaded = pacer.threaded_next();
    threaded_count += threaded ? 1 : 0;
    pacer.record(threaded, cost(threaded, k, last_serial), 1.0);
    last_serial = !threaded;
  }
  return threaded_count;
}

/// Threads that never pay, serial runs of which every fourth is descheduled (ten times its
/// usual time): the descheduled runs must not make the threads look fast, so only the probes,
/// at most kMaxSkip runs apart once backed off, are threaded.
TEST(ThreadPacer, DescheduledSerialRunsDoNotKeepSlowThreads) {
  ThreadPacer pacer(0.95);
  const int runs = 4000;
  int serial_k = 0;
  const int threaded = threaded_runs(pacer, runs, [&](bool t, int, bool) {
    if (t) return 1.2;
    return ++serial_k % 4 == 0 ? 10.0 : 1.0;
  });
  // The backoff grows 1, 2, 4, …, kMaxSkip: ~log2(kMaxSkip) probes, then one per kMaxSkip runs.
  EXPECT_LE(threaded, 2 * runs / ThreadPacer::kMaxSkip + 16);
  EXPECT_GE(threaded, runs / (ThreadPacer::kMaxSkip + 1));  // the probes go on
}

/// A busy machine's threads: the probe right after serial runs is fast (both members happened
/// to run), every threaded run after it stalls. A lucky probe must not reset the backoff, so
/// the probes stay far apart and at most one stalled run follows each.
TEST(ThreadPacer, LuckyProbesDoNotBringTheThreadsBack) {
  ThreadPacer pacer(0.95);
  const int runs = 4000;
  const int threaded = threaded_runs(pacer, runs, [](bool t, int, bool after_serial) {
    if (!t) return 1.0;
    return after_serial ? 0.5 : 3.0;
  });
  EXPECT_LE(threaded, 4 * runs / ThreadPacer::kMaxSkip + 32);
}

/// A free machine: threads at half the serial time are kept on all but the serial refresh runs,
/// also when serial runs are now and then descheduled; after a busy spell they come back, and
/// a few paying runs later one stalled run costs a single serial run, not a long backoff.
TEST(ThreadPacer, PayingThreadsAreKeptAndComeBackAfterABusySpell) {
  ThreadPacer pacer(0.95);
  int serial_k = 0;
  auto free_machine = [&](bool t, int, bool) { return t ? 0.5 : ++serial_k % 5 == 0 ? 8.0 : 1.0; };
  const int runs = 40 * (ThreadPacer::kRefresh + 1);
  EXPECT_GE(threaded_runs(pacer, runs, free_machine), runs - runs / ThreadPacer::kRefresh - 4);
  // Busy: threads slower than serial; the pacer backs off to kMaxSkip.
  threaded_runs(pacer, 20 * ThreadPacer::kMaxSkip, [](bool t, int, bool) { return t ? 2.0 : 1.0; });
  while (!pacer.threaded_next()) pacer.record(false, 1.0, 1.0);
  pacer.record(true, 2.0, 1.0);
  // Free again: the threads are back after kMaxSkip serial runs …
  int until = 0;
  for (; !pacer.threaded_next() && until <= ThreadPacer::kMaxSkip; ++until) pacer.record(false, 1.0, 1.0);
  EXPECT_EQ(ThreadPacer::kMaxSkip, until);
  threaded_runs(pacer, 16, free_machine);  // paying runs after the probe halve the backoff down to 1
  // … and one stalled threaded run then skips one run only.
  while (!pacer.threaded_next()) pacer.record(false, 1.0, 1.0);
  pacer.record(true, 5.0, 1.0);
  EXPECT_FALSE(pacer.threaded_next());
  pacer.record(false, 1.0, 1.0);
  EXPECT_TRUE(pacer.threaded_next());
}

/// The first run is threaded, and the first serial run judges it: threads slower than that
/// serial run are not tried again at once (a fresh World on a busy machine probes less).
TEST(ThreadPacer, TheFirstSerialRunJudgesTheFirstThreadedRun) {
  ThreadPacer slow(0.95), fast(0.95);
  ASSERT_TRUE(slow.threaded_next());
  slow.record(true, 2.0, 1.0);
  ASSERT_FALSE(slow.threaded_next());
  slow.record(false, 1.0, 1.0);
  EXPECT_FALSE(slow.threaded_next());
  slow.record(false, 1.0, 1.0);
  EXPECT_TRUE(slow.threaded_next());  // the probe after a backoff of one run
  fast.record(true, 0.5, 1.0);
  fast.record(false, 1.0, 1.0);
  EXPECT_TRUE(fast.threaded_next());
}

/// A shared host whose speed drifts: serial runs cost 2 while threads cost 1.5 (they pay),
/// then the machine turns faster, serial runs cost 1 and threads still 1.5 (they do not pay).
/// The median of the serial runs still holds the slow spell; the first serial run after the
/// change (at most a refresh away) must drop the threads at the next threaded run, and the
/// serial runs after it keep them off but for the probes.
TEST(ThreadPacer, ThreadsAreJudgedAgainstTheLatestSerialRunWhenTheMachineTurnsFaster) {
  ThreadPacer pacer(0.9);
  const int slow_runs = 10 * (ThreadPacer::kRefresh + 1);
  const int slow_threaded = threaded_runs(pacer, slow_runs, [](bool t, int, bool) { return t ? 1.5 : 2.0; });
  EXPECT_GE(slow_threaded, slow_runs - slow_runs / ThreadPacer::kRefresh - 4);  // paying threads kept
  const int fast_runs = 40 * ThreadPacer::kRefresh;
  const int fast_threaded = threaded_runs(pacer, fast_runs, [](bool t, int, bool) { return t ? 1.5 : 1.0; });
  // At most one refresh interval of threaded runs before the first fresh serial run, then the
  // probes of the backoff (1, 2, 4, …, kMaxSkip apart).
  EXPECT_LE(fast_threaded, ThreadPacer::kRefresh + 2 * fast_runs / ThreadPacer::kMaxSkip + 16);
}

/// proven(): threaded runs measured since the last backoff that pay against the serial reference
/// (the lesser of the serial median and the latest serial run).
TEST(ThreadPacer, ProvenOnlyAfterPayingThreadedRuns) {
  ThreadPacer pacer;
  EXPECT_FALSE(pacer.proven());
  pacer.record(true, 0.5, 1.0);
  EXPECT_FALSE(pacer.proven());  // no serial run to compare with
  pacer.record(false, 1.0, 1.0);
  EXPECT_TRUE(pacer.proven());
  pacer.record(true, 2.0, 1.0);  // the average now exceeds kPays × serial: backed off
  EXPECT_FALSE(pacer.proven());
  EXPECT_FALSE(pacer.threaded_next());
}

}  // namespace
}  // namespace dc
