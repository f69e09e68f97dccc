#pragma once
// A one-line progress bar on stderr, drawn only when stderr is a terminal (so logs and CI
// output stay clean). Thread-safe: several OpenMP workers may call advance().
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <unistd.h>

namespace dc::bench {

class ProgressBar {
 public:
  ProgressBar(std::string label, long total, bool enabled = ::isatty(STDERR_FILENO) != 0)
      : label_(std::move(label)), total_(total > 0 ? total : 1), enabled_(enabled),
        start_(std::chrono::steady_clock::now()) {
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
    if (!enabled_ || finished_) return;
    const auto now = std::chrono::steady_clock::now();
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

  std::string label_, note_;
  long total_, done_ = 0;
  bool enabled_, finished_ = false;
  std::chrono::steady_clock::time_point start_, last_{};
  std::mutex mutex_;
};

}  // namespace dc::bench
