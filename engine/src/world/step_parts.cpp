#include "world/step_parts.hpp"

#include <algorithm>
#include <exception>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace dc {

void run_parts(int threads, int parts, PartJob job) {
  if (threads <= 1 || parts <= 1) {  // (no parallel region: libgomp allocates a team even for a serial one)
    for (int p = 0; p < parts; ++p) job(p);
    return;
  }
  std::exception_ptr error;
#pragma omp parallel for num_threads(std::min(threads, parts)) schedule(dynamic, 1)
  for (int p = 0; p < parts; ++p) {
    try {
      job(p);
    } catch (...) {
#pragma omp critical(dc_run_parts_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

void release_threads() {
#if defined(_OPENMP)
  (void)omp_pause_resource_all(omp_pause_soft);
#endif
}

int parts_for(int threads, long items, int per_thread, long min_items) {
  if (threads <= 1) return 1;
  const long most = std::max(1L, items / std::max(1L, min_items));
  return static_cast<int>(std::clamp<long>(static_cast<long>(threads) * per_thread, 1, most));
}

}  // namespace dc
