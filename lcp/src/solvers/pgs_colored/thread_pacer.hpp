#pragma once
// Whether pgs-colored's solves run on threads: only problems large enough (threads_for), and only
// while threads pay (dc/core/thread_pacer.hpp). The thread count never changes a result
// (pgs_colored.cpp), only the time it takes.
#include <algorithm>
#include <cstddef>

#include "dc/core/thread_pacer.hpp"

namespace dc::colored {

/// Threads for `batches` batches of 8 contacts swept in `ranges` colour ranges (each a wait
/// between the threads per sweep): `requested` when the ranges average at least
/// `min_per_thread` batches per thread (0: always), else 1, so small problems stay on one thread.
inline int threads_for(int requested, int min_per_thread, long batches, std::size_t ranges) {
  const long need = static_cast<long>(std::max(0, min_per_thread)) * requested *
                    static_cast<long>(std::max<std::size_t>(1, ranges));
  return requested > 1 && batches >= need ? requested : 1;
}

using ThreadPacer = dc::ThreadPacer;

}  // namespace dc::colored
