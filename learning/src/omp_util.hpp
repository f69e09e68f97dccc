#pragma once
// Private OpenMP helpers: the library compiles with OpenMP, but keep the calls in one place.
#include <omp.h>

namespace dc::detail {

/// Threads a parallel region will use (fixed for a given OMP_NUM_THREADS / set_num_threads).
inline int max_threads() { return omp_get_max_threads(); }
inline int thread_id() { return omp_get_thread_num(); }

/// ⌊a / b⌋ for b > 0 and any sign of a (C++ '/' truncates towards zero).
inline int floor_div(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
inline int ceil_div(int a, int b) { return -floor_div(-a, b); }

}  // namespace dc::detail
