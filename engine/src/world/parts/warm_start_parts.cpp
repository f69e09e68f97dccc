#include "world/parts/warm_start_parts.hpp"

#include <algorithm>
#include <atomic>

#include "dc/engine/matched_lambda.hpp"
#include "world/parts/step_parts.hpp"

namespace dc {

void previous_lambda(const std::vector<Contact>& previous, const std::vector<Contact>& current,
                     const LcpProblem& problem, int threads, KeptVector& out, std::vector<long>& starts) {
  const long nc = static_cast<long>(current.size());
  const int jobs = parts_for(threads, nc, 4, 1024);
  if (jobs <= 1 || problem.constraints.size() != nc || problem.constraints.rows() != problem.rows())
    return put_matched_lambda(previous, current, problem, out);
  // Where each job's merge starts in `previous`: ascending when both lists are sorted.
  const long np = static_cast<long>(previous.size());
  std::vector<long>& start = starts;
  start.assign(static_cast<size_t>(jobs) + 1, np);
  start[0] = 0;
  for (int p = 1; p < jobs; ++p) {
    const ContactKey& key = current[static_cast<size_t>(part_begin(nc, jobs, p))].key;
    start[static_cast<size_t>(p)] =
        std::lower_bound(previous.begin(), previous.end(), key, [](const Contact& a, const ContactKey& k) { return a.key < k; }) -
        previous.begin();
  }
  if (!std::is_sorted(start.begin(), start.end())) return put_matched_lambda(previous, current, problem, out);  // (it throws)
  out.resize(problem.rows());
  std::atomic<bool> failed{false};  // a list out of order, or rows project_contact does not cover
  run_parts(threads, jobs, [&](int p) {
    const long c0 = part_begin(nc, jobs, p), c1 = part_begin(nc, jobs, p + 1);
    const long j0 = start[static_cast<size_t>(p)], j1 = start[static_cast<size_t>(p) + 1];
    bool ok = true;
    long j = j0;
    for (long c = c0; c < c1; ++c) {
      const ContactKey& key = current[static_cast<size_t>(c)].key;
      if (c > 0 && key < current[static_cast<size_t>(c - 1)].key) ok = false;
      while (j < np && previous[static_cast<size_t>(j)].key < key) ++j;
      const bool found = j < np && previous[static_cast<size_t>(j)].key == key;
      const Contact* prev = found ? &previous[static_cast<size_t>(j)] : nullptr;
      problem.constraints.put(static_cast<int>(c), prev ? prev->lambda_n : 0.0, prev ? prev->lambda_t : 0.0, out);
      ok = ok && project_contact_rows(problem, static_cast<int>(c), out);
    }
    // This job's stretch of `previous` in order (the stretches cover it).
    for (long q = j0; q + 1 < std::min(j1 + 1, np); ++q)
      if (previous[static_cast<size_t>(q + 1)].key < previous[static_cast<size_t>(q)].key) ok = false;
    if (!ok) failed.store(true, std::memory_order_relaxed);
  });
  if (failed.load()) put_matched_lambda(previous, current, problem, out);  // its check throws the message
}

}  // namespace dc
