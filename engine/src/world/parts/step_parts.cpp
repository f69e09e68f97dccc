#include "world/parts/step_parts.hpp"

#include <algorithm>

namespace dc {

void run_parts(int threads, int parts, PartJob job) { calling_thread_team().for_parts(threads, parts, job); }

int parts_for(int threads, long items, int per_thread, long min_items) {
  if (threads <= 1) return 1;
  const long most = std::max(1L, items / std::max(1L, min_items));
  return static_cast<int>(std::clamp<long>(static_cast<long>(threads) * per_thread, 1, most));
}

}  // namespace dc
