// CPU time of the calling thread, for the network's per-layer and the inference plan's
// per-step profiles (private to dc_learning).
#pragma once

#include <ctime>

namespace dc::detail {

/// CPU time of the calling thread [ms]. Profiles use it rather than wall time because on a
/// loaded machine wall time would count the time the thread was descheduled.
inline double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

}  // namespace dc::detail
