#pragma once
// Threads only while they pay: the wall time per unit of work of threaded and of serial runs of
// one task (a pgs-colored solve, the engine stages of a World step) is kept as two moving
// averages; when threaded runs are not at least 1 / pays times faster (default kPays), e.g.
// with the other core busy with another program, the next runs are serial, for 1, 2, 4, … up
// to kMaxSkip runs between threaded probes; a serial probe after every kRefresh threaded runs keeps the serial figure
// current. The thread count of a run never changes its result, only the time it takes.
#include <algorithm>

namespace dc {

class ThreadPacer {
 public:
  static constexpr double kPays = 0.9;   // threaded / serial time per unit of work to keep the threads (default)
  /// `pays`: the ratio threaded / serial time per unit of work at most which the threads are kept.
  explicit ThreadPacer(double pays = kPays) : pays_(pays) {}
  static constexpr double kWeight = 0.3; // weight of the newest run in the moving averages
  static constexpr int kMaxSkip = 64;
  static constexpr int kRefresh = 32;

  /// True when the next run should use the threads.
  [[nodiscard]] bool threaded_next() const { return skip_ == 0 && !(serial_ == 0.0 && threaded_ > 0.0); }

  /// True when the threaded runs measured since the last backoff paid (pgs-colored runs its
  /// set-up's parallel regions, whose waits cannot hand a descheduled thread's share to another,
  /// on the threads only then, not on probes).
  [[nodiscard]] bool proven() const { return serial_ > 0.0 && threaded_ > 0.0 && threaded_ <= pays_ * serial_; }

  /// A run of `work` units (> 0) took `seconds` of wall time, threaded or not.
  void record(bool threaded, double seconds, double work) {
    const double c = seconds / work;
    if (!threaded) {
      serial_ = average(serial_, c);
      if (skip_ > 0) --skip_;
      return;
    }
    threaded_ = average(threaded_, c);
    if (serial_ > 0.0 && threaded_ > pays_ * serial_) {
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

  double pays_;
  double serial_ = 0.0, threaded_ = 0.0;  // s per unit of work; 0 = not yet measured
  int skip_ = 0;                          // serial runs before the next threaded one
  int backoff_ = 1;
  int since_serial_ = 0;
};

}  // namespace dc
