#pragma once
// Threads only while they pay: the wall time per unit of work of threaded and of serial runs of
// one task (a pgs-colored solve, the engine stages of a World step) decides; when threaded runs
// are not at least 1 / pays times faster (default kPays), e.g. with the other core busy with
// another program, the next runs are serial, for 1, 2, 4, … up to kMaxSkip runs between
// threaded probes; a serial probe after every kRefresh threaded runs keeps the serial figure
// current. The thread count of a run never changes its result, only the time it takes.
//
// On a busy machine a run's wall time has a heavy tail: a serial run descheduled for a time
// slice takes several times its usual time, and a threaded run stalls whenever either member is
// descheduled mid-run (the other waits for its claimed work at the next barrier), which happens
// more often than to one thread. The two figures are therefore kept differently: the serial one
// is the median of the last kSerialRuns serial runs (one descheduled run cannot make the threads
// look fast), the threaded one a moving average (kWeight) restarted at each probe (one stalled
// run drops the threads at once). A probe that pays keeps the threads but not yet the backoff;
// each paying threaded run after it halves the backoff. On a busy machine, where a probe is
// often lucky and the runs after it stall, the probes thus stay up to kMaxSkip runs apart; on
// a free machine a few paying runs bring the backoff back to 1.
//
// The serial runs' noise is one-sided (a descheduled run is slower, no run is faster than the
// machine allows), but the machine's own speed may drift within minutes on a shared host (a
// neighbour's load, frequency): a median of serial runs from a slower spell would make threads
// that do not pay now look paying until fresher serial runs fill it. Threads are therefore
// judged against the lesser of the median and the latest serial run: the refresh run after a
// change of speed drops threads that stopped paying at the next threaded run.
#include <algorithm>
#include <array>

namespace dc {

class ThreadPacer {
 public:
  static constexpr double kPays = 0.9;   // threaded / serial time per unit of work to keep the threads (default)
  /// `pays`: the ratio threaded / serial time per unit of work at most which the threads are kept.
  explicit ThreadPacer(double pays = kPays) : pays_(pays) {}
  static constexpr double kWeight = 0.3;  // weight of the newest threaded run in the threaded moving average
  static constexpr int kSerialRuns = 7;   // the serial figure: the median of this many last serial runs
  static constexpr int kMaxSkip = 64;
  static constexpr int kRefresh = 32;

  /// True when the next run should use the threads.
  [[nodiscard]] bool threaded_next() const { return skip_ == 0 && !(serial_count_ == 0 && threaded_ > 0.0); }

  /// True when the threaded runs measured since the last backoff paid (pgs-colored runs its
  /// set-up's parallel regions, whose waits cannot hand a descheduled thread's share to another,
  /// on the threads only then, not on probes).
  [[nodiscard]] bool proven() const {
    const double serial = serial_reference();
    return serial > 0.0 && threaded_ > 0.0 && threaded_ <= pays_ * serial;
  }

  /// A run of `work` units (> 0) took `seconds` of wall time, threaded or not.
  void record(bool threaded, double seconds, double work) {
    const double c = seconds / work;
    if (!threaded) {
      serial_[static_cast<size_t>(serial_next_)] = c;
      serial_next_ = (serial_next_ + 1) % kSerialRuns;
      serial_count_ = std::min(serial_count_ + 1, kSerialRuns);
      last_serial_ = c;
      if (skip_ > 0) --skip_;
      // The first serial run judges the threaded runs before it (the very first run is threaded).
      if (serial_count_ == 1 && threaded_ > pays_ * c) back_off();
      return;
    }
    threaded_ = threaded_ == 0.0 ? c : (1.0 - kWeight) * threaded_ + kWeight * c;
    const double serial = serial_reference();
    if (serial > 0.0 && threaded_ > pays_ * serial) {
      back_off();
    } else if (serial > 0.0) {
      if (!probing_) backoff_ = std::max(1, backoff_ / 2);
      probing_ = false;
      if (++since_serial_ >= kRefresh) {
        skip_ = 1;
        since_serial_ = 0;
      }
    }
  }

 private:
  /// Threads that do not pay: the next `backoff_` runs serial, the backoff doubled.
  void back_off() {
    skip_ = std::max(skip_, backoff_);
    backoff_ = std::min(2 * backoff_, kMaxSkip);
    threaded_ = 0.0;  // the next probe is judged on its own
    since_serial_ = 0;
    probing_ = true;
  }

  /// The median of the stored serial runs (s per unit of work; 0 = none yet).
  [[nodiscard]] double serial_figure() const {
    if (serial_count_ == 0) return 0.0;
    std::array<double, kSerialRuns> v = serial_;
    const auto end = v.begin() + serial_count_;
    const auto mid = v.begin() + serial_count_ / 2;
    std::nth_element(v.begin(), mid, end);
    if (serial_count_ % 2 != 0) return *mid;
    return 0.5 * (*mid + *std::max_element(v.begin(), mid));
  }

  /// What threaded runs are judged against: the lesser of the median and the latest serial run.
  [[nodiscard]] double serial_reference() const {
    return serial_count_ == 0 ? 0.0 : std::min(serial_figure(), last_serial_);
  }

  double pays_;
  double last_serial_ = 0.0;  // the latest serial run, s per unit of work
  std::array<double, kSerialRuns> serial_{};  // the last serial runs, s per unit of work (a ring)
  int serial_next_ = 0, serial_count_ = 0;
  double threaded_ = 0.0;  // s per unit of work; 0 = not measured since the last backoff
  int skip_ = 0;           // serial runs before the next threaded one
  int backoff_ = 1;
  bool probing_ = false;  // the next threaded run is a probe after a backoff
  int since_serial_ = 0;
};

}  // namespace dc
