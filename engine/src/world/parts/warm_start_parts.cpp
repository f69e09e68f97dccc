#include "world/parts/warm_start_parts.hpp"

#include <algorithm>
#include <atomic>

#include "dc/engine/matched_lambda.hpp"
#include "world/parts/step_parts.hpp"

namespace dc {

void previous_lambda(const std::vector<Contact>& previous, std::span<const ContactLambda> previous_lambdas,
                     const std::vector<Contact>& current, const LcpProblem& problem, int threads, KeptVector& out,
                     std::vector<long>& starts) {
  const bool packed = !previous_lambdas.empty() || previous.empty();
  // The serial merge (also the one whose checks throw the message).
  const auto serial = [&] {
    if (packed) return put_matched_lambda(previous, previous_lambdas, current, problem, out);
    put_matched_lambda(previous, current, problem, out);
  };
  if (packed && previous_lambdas.size() != previous.size()) return serial();  // (it throws)
  const long nc = static_cast<long>(current.size());
  const int jobs = parts_for(threads, nc, 4, 1024);
  if (jobs <= 1 || problem.constraints.size() != nc || problem.constraints.rows() != problem.rows())
    return serial();
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
  if (!std::is_sorted(start.begin(), start.end())) return serial();  // (it throws)
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
      ContactLambda l;  // (0, 0) for a new contact
      if (found) {
        const auto k = static_cast<size_t>(j);
        l = packed ? previous_lambdas[k] : ContactLambda{previous[k].lambda_n, previous[k].lambda_t};
      }
      problem.constraints.put(static_cast<int>(c), l.n, l.t, out);
      ok = ok && project_contact_rows(problem, static_cast<int>(c), out);
    }
    // This job's stretch of `previous` in order (the stretches cover it).
    for (long q = j0; q + 1 < std::min(j1 + 1, np); ++q)
      if (previous[static_cast<size_t>(q + 1)].key < previous[static_cast<size_t>(q)].key) ok = false;
    if (!ok) failed.store(true, std::memory_order_relaxed);
  });
  if (failed.load()) serial();  // its check throws the message
}

}  // namespace dc
