#pragma once
// A one-line progress bar on stderr when stderr is a terminal. Otherwise (output to a file or
// a pipe, CI) a plain heartbeat line instead, "bench: 1200/4800 (25%), 120 s elapsed, ETA
// 360 s", every kHeartbeat seconds of a run (none for a run shorter than that), so a log
// shows that a long run is alive and how far it is. Thread-safe: several OpenMP workers may
// call advance().
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <unistd.h>

namespace dc::bench {

class ProgressBar {
 public:
  /// Seconds between heartbeat lines when stderr is not a terminal.
  static constexpr std::chrono::milliseconds kHeartbeat{5000};

  /// `enabled`: draw the bar (stderr is a terminal); otherwise a heartbeat line every
  /// `heartbeat` (tests pass 0: a line at every advance).
  ProgressBar(std::string label, long total, bool enabled = ::isatty(STDERR_FILENO) != 0,
              std::chrono::milliseconds heartbeat = kHeartbeat)
      : label_(std::move(label)), total_(total > 0 ? total : 1), enabled_(enabled), heartbeat_(heartbeat),
        start_(std::chrono::steady_clock::now()), last_(enabled ? std::chrono::steady_clock::time_point{} : start_) {
    draw();
  }
  ~ProgressBar() { finish(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void advance(long n = 1, const std::string& note = {}) {
    std::lock_guard lock(mutex_);
    done_ += n;
    if (!note.empty()) note_ = note;
    draw_locked();
  }
  void finish() {
    std::lock_guard lock(mutex_);
    if (enabled_ && !finished_) std::fputc('\n', stderr);
    finished_ = true;
  }

 private:
  void draw() { std::lock_guard lock(mutex_); draw_locked(); }
  void draw_locked() {
    if (finished_) return;
    const auto now = std::chrono::steady_clock::now();
    if (!enabled_) {
      heartbeat_locked(now);
      return;
    }
    if (done_ < total_ && now - last_ < std::chrono::milliseconds(100)) return;  // ≤ 10 Hz
    last_ = now;
    const double frac = static_cast<double>(done_) / static_cast<double>(total_);
    const double el = std::chrono::duration<double>(now - start_).count();
    const double eta = frac > 0 ? el * (1 - frac) / frac : 0;
    constexpr int width = 30;
    const int fill = static_cast<int>(frac * width);
    std::string bar(static_cast<size_t>(fill), '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r%s [%s] %ld/%ld %3.0f%% %5.0fs ETA %5.0fs %s\033[K", label_.c_str(),
                 bar.c_str(), done_, total_, 100 * frac, el, eta, note_.c_str());
    std::fflush(stderr);
  }

  void heartbeat_locked(std::chrono::steady_clock::time_point now) {
    if (now - last_ < heartbeat_ || done_ >= total_) return;
    last_ = now;
    const double frac = static_cast<double>(done_) / static_cast<double>(total_);
    const double el = std::chrono::duration<double>(now - start_).count();
    std::fprintf(stderr, "%s: %ld/%ld (%.0f%%), %.0f s elapsed, ETA %.0f s%s%s\n", label_.c_str(), done_, total_,
                 100 * frac, el, frac > 0 ? el * (1 - frac) / frac : 0.0, note_.empty() ? "" : ", ", note_.c_str());
    std::fflush(stderr);
  }

  std::string label_, note_;
  long total_, done_ = 0;
  bool enabled_, finished_ = false;
  std::chrono::milliseconds heartbeat_;
  std::chrono::steady_clock::time_point start_, last_{};
  std::mutex mutex_;
};

}  // namespace dc::bench
