#pragma once
// Waiting between the threads of a team (work_team.hpp, pgs-colored's sweeps) on a shared
// machine: spin briefly (the other thread is usually microseconds away), then yield the core (the awaited thread may be
// queued behind another program on it), then sleep on a futex until notified. A waiter that
// sleeps costs the notifier one system call; one that never sleeps costs it one atomic load.
// Protocol: a waiter reads the word, counts itself in `sleepers`, checks its condition and sleeps
// only while the word is unchanged; a notifier makes the condition true, then, if any waiter is
// counted, changes the word and wakes all.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cstdint>
#include <thread>

#if defined(__linux__)
#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <ctime>
#endif

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace dc {

/// One wake-up word for a team of threads: wait(ready) returns once ready() is true; whoever
/// makes a condition true calls notify() afterwards. All operations are sequentially
/// consistent, so a waiter about to sleep either sees the condition or is woken.
class WakeWord {
 public:
  /// Spin time before yielding, and spin + yield time before sleeping [µs].
  static constexpr int kSpinMicros = 10;
  static constexpr int kYieldMicros = 200;

  /// Waits until ready(); each futex sleep lasts at most `sleep_limit_us` (a missed wake-up
  /// costs that much; an idle team's helpers sleep longer than the threads of a solve).
  template <class Ready>
  void wait(Ready&& ready, long sleep_limit_us = 1000) {
    if (ready()) return;
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    for (int i = 1;; ++i) {
      if (ready()) return;
      relax();
      if ((i & 63) == 0 && Clock::now() - start > std::chrono::microseconds(kSpinMicros)) break;
    }
    while (Clock::now() - start < std::chrono::microseconds(kYieldMicros)) {
      if (ready()) return;
      std::this_thread::yield();
    }
    for (;;) {
      const std::uint32_t seen = word_.load();
      if (ready()) return;
      sleepers_.fetch_add(1);
      if (!ready()) sleep(seen, sleep_limit_us);
      sleepers_.fetch_sub(1);
    }
  }

  /// Some waiter is counted as (about to be) asleep: a notifier that must read shared state to
  /// decide whether its condition became true can skip that read while this is false (the
  /// spinning waiters see the condition themselves; a waiter counted later checks it then).
  [[nodiscard]] bool sleeping() const { return sleepers_.load() != 0; }

  /// After making a condition true: wakes the sleeping waiters, if any (one load otherwise);
  /// true when it made the wake-up call.
  bool notify() {
    if (sleepers_.load() == 0) return false;  // a waiter not yet counted sees the condition when counted
    word_.fetch_add(1);
    wake_all();
    return true;
  }

 private:
  static void relax() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
  }

  /// Sleeps while the word still holds `seen`, for at most limit_us.
  void sleep(std::uint32_t seen, long limit_us) {
#if defined(__linux__)
    const timespec limit{limit_us / 1000000, 1000 * (limit_us % 1000000)};
    syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word_), FUTEX_WAIT_PRIVATE, seen, &limit, nullptr, 0);
#else
    if (word_.load() == seen) std::this_thread::sleep_for(std::chrono::microseconds(std::min(50L, limit_us)));
#endif
  }

  void wake_all() {
#if defined(__linux__)
    syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word_), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr, 0);
#endif
  }

  static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t));
  alignas(64) std::atomic<std::uint32_t> word_{0};
  std::atomic<int> sleepers_{0};
};

}  // namespace dc
