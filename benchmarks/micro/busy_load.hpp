#pragma once
// Competitor load for thread-scaling measurements (step_threads --load K): K child processes at
// the caller's nice level, each spinning on plain floating-point arithmetic (no memory traffic,
// not the engine), from start() to stop(). Processes, not threads, so that the measuring
// process's CPU clocks (CLOCK_PROCESS_CPUTIME_ID) count none of their time. Each child ends with
// the parent (PR_SET_PDEATHSIG) if stop() is never reached. The child calls only system calls
// after fork() (the parent has threads: its team's helpers), so nothing it inherits is touched.
#include <csignal>
#include <cstdio>
#include <ctime>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace dc::bench {

class BusyLoad {
 public:
  BusyLoad() = default;
  BusyLoad(const BusyLoad&) = delete;
  BusyLoad& operator=(const BusyLoad&) = delete;
  ~BusyLoad() { stop(); }

  /// Starts `count` spinning children (none for count ≤ 0).
  void start(int count) {
    stop();
    const pid_t parent = getpid();
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    start_s_ = static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
    for (int i = 0; i < count; ++i) {
      const pid_t pid = fork();
      if (pid < 0) throw std::runtime_error("--load: fork failed");
      if (pid == 0) spin(parent);
      children_.push_back(pid);
    }
  }

  /// Ends the children; the mean share of one core each got while it ran (0 without children).
  double stop() {
    if (children_.empty()) return 0.0;
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    const double wall = static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec) - start_s_;
    double cpu = 0.0;
    for (const pid_t pid : children_) {
      kill(pid, SIGKILL);
      int status = 0;
      rusage use{};
      if (wait4(pid, &status, 0, &use) == pid)
        cpu += static_cast<double>(use.ru_utime.tv_sec + use.ru_stime.tv_sec) +
               1e-6 * static_cast<double>(use.ru_utime.tv_usec + use.ru_stime.tv_usec);
    }
    const double share = wall > 0.0 ? cpu / wall / static_cast<double>(children_.size()) : 0.0;
    children_.clear();
    return share;
  }

 private:
  /// The child: arithmetic until killed (or the parent is gone).
  [[noreturn]] static void spin(pid_t parent) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(0);  // the parent ended before the line above
    double x = 1.0;
    for (;;) {
      for (int i = 0; i < 1 << 20; ++i) x = x * 0.9999999 + 1e-7;  // tends to 1: no overflow, no denormals
      if (x < 0.0 || getppid() != parent) _exit(0);                 // (x is read: the loop stays)
    }
  }

  std::vector<pid_t> children_;
  double start_s_ = 0.0;
};

/// The CPU model (/proc/cpuinfo's first "model name"), or "unknown".
inline std::string cpu_model() {
  FILE* f = std::fopen("/proc/cpuinfo", "r");
  if (f == nullptr) return "unknown";
  char line[512];
  std::string model = "unknown";
  while (std::fgets(line, sizeof line, f) != nullptr) {
    const std::string s(line);
    if (s.rfind("model name", 0) != 0) continue;
    const size_t colon = s.find(':');
    if (colon != std::string::npos) model = s.substr(colon + 2, s.size() - colon - 3);
    break;
  }
  std::fclose(f);
  return model;
}

}  // namespace dc::bench
