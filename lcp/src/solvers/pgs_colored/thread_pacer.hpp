#pragma once
// Whether pgs-colored's solves run on threads: only problems large enough (threads_for), and only
// while threads pay (ThreadPacer: the wall time per unit of work of threaded and of serial solves
// is kept as two moving averages; when threaded solves are not at least 1 / kPays times faster,
// e.g. with the other core busy with another program, the next solves run serially, for 1, 2,
// 4, … up to kMaxSkip solves between threaded probes; a serial probe after every kRefresh
// threaded solves keeps the serial figure current). The thread count never changes a result
// (pgs_colored.cpp), only the time it takes.
#include <algorithm>
#include <cstddef>

namespace dc::colored {

/// Threads for `batches` batches of 8 contacts swept in `ranges` colour ranges (each a wait
/// between the threads per sweep): `requested` when the ranges average at least
/// `min_per_thread` batches per thread (0: always), else 1, so small problems stay on one thread.
inline int threads_for(int requested, int min_per_thread, long batches, std::size_t ranges) {
  const long need = static_cast<long>(std::max(0, min_per_thread)) * requested *
                    static_cast<long>(std::max<std::size_t>(1, ranges));
  return requested > 1 && batches >= need ? requested : 1;
}

class ThreadPacer {
 public:
  static constexpr double kPays = 0.9;   // threaded / serial time per unit of work to keep the threads
  static constexpr double kWeight = 0.3; // weight of the newest solve in the moving averages
  static constexpr int kMaxSkip = 64;
  static constexpr int kRefresh = 32;

  /// True when the next solve should use the threads.
  [[nodiscard]] bool threaded_next() const { return skip_ == 0 && !(serial_ == 0.0 && threaded_ > 0.0); }

  /// True when the threaded solves measured since the last backoff paid: the set-up's parallel
  /// regions (whose waits cannot hand a descheduled thread's share to another) run on the
  /// threads only then, not on probes.
  [[nodiscard]] bool proven() const { return serial_ > 0.0 && threaded_ > 0.0 && threaded_ <= kPays * serial_; }

  /// A solve of `work` units (> 0) took `seconds` of wall time, threaded or not.
  void record(bool threaded, double seconds, double work) {
    const double c = seconds / work;
    if (!threaded) {
      serial_ = average(serial_, c);
      if (skip_ > 0) --skip_;
      return;
    }
    threaded_ = average(threaded_, c);
    if (serial_ > 0.0 && threaded_ > kPays * serial_) {
      skip_ = backoff_;
      backoff_ = std::min(2 * backoff_, kMaxSkip);
      threaded_ = 0.0;  // the next probe is judged on its own
      since_serial_ = 0;
    } else if (serial_ > 0.0) {
      backoff_ = 1;
      if (++since_serial_ >= kRefresh) {
        skip_ = 1;
        since_serial_ = 0;
      }
    }
  }

 private:
  static double average(double old, double c) { return old == 0.0 ? c : (1.0 - kWeight) * old + kWeight * c; }

  double serial_ = 0.0, threaded_ = 0.0;  // s per unit of work; 0 = not yet measured
  int skip_ = 0;                          // serial solves before the next threaded one
  int backoff_ = 1;
  int since_serial_ = 0;
};

}  // namespace dc::colored
