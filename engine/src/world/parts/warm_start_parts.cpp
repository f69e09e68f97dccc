#include "world/parts/warm_start_parts.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "dc/engine/contact_match.hpp"
#include "world/parts/step_parts.hpp"

namespace dc {
namespace {

/// The one-thread form: match, put, project.
Eigen::VectorXd serial_lambda(const std::vector<Contact>& previous, const std::vector<Contact>& current,
                              const LcpProblem& problem) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(problem.rows());
  for_each_matched_contact(previous, current, [&](std::size_t c, const Contact& p) {
    problem.constraints.put(static_cast<int>(c), p.lambda_n, p.lambda_t, out);
  });
  project_feasible(problem, out);
  return out;
}

/// project_feasible on contact c's rows: its normal row (not a friction row), then its tangent
/// row, whose bounds read that normal row only. False when the rows are not so related (then
/// nothing is written).
bool project_contact(const LcpProblem& p, int c, Eigen::VectorXd& lambda) {
  const ContactConstraint& k = p.constraints[c];
  if (p.is_friction_row(k.normal_row) || (k.tangent_row >= 0 && p.normal_row[static_cast<size_t>(k.tangent_row)] != k.normal_row))
    return false;
  double& n = lambda[k.normal_row];
  if (!std::isfinite(n)) n = 0.0;
  n = std::clamp(n, p.lo[k.normal_row], p.hi[k.normal_row]);
  if (k.tangent_row >= 0) {
    double& t = lambda[k.tangent_row];
    if (!std::isfinite(t)) t = 0.0;
    t = std::clamp(t, p.lower(k.tangent_row, lambda), p.upper(k.tangent_row, lambda));
  }
  return true;
}

}  // namespace

Eigen::VectorXd previous_lambda(const std::vector<Contact>& previous, const std::vector<Contact>& current,
                                const LcpProblem& problem, int threads) {
  const long nc = static_cast<long>(current.size());
  const int jobs = parts_for(threads, nc, 4, 1024);
  if (jobs <= 1 || problem.constraints.size() != nc || problem.constraints.rows() != problem.rows())
    return serial_lambda(previous, current, problem);
  // Where each job's merge starts in `previous`: ascending when both lists are sorted.
  const long np = static_cast<long>(previous.size());
  std::vector<long> start(static_cast<size_t>(jobs) + 1, np);
  start[0] = 0;
  for (int p = 1; p < jobs; ++p) {
    const ContactKey& key = current[static_cast<size_t>(part_begin(nc, jobs, p))].key;
    start[static_cast<size_t>(p)] =
        std::lower_bound(previous.begin(), previous.end(), key, [](const Contact& a, const ContactKey& k) { return a.key < k; }) -
        previous.begin();
  }
  if (!std::is_sorted(start.begin(), start.end())) return serial_lambda(previous, current, problem);  // (it throws)
  Eigen::VectorXd out(problem.rows());
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
      ok = ok && project_contact(problem, static_cast<int>(c), out);
    }
    // This job's stretch of `previous` in order (the stretches cover it).
    for (long q = j0; q + 1 < std::min(j1 + 1, np); ++q)
      if (previous[static_cast<size_t>(q + 1)].key < previous[static_cast<size_t>(q)].key) ok = false;
    if (!ok) failed.store(true, std::memory_order_relaxed);
  });
  if (failed.load()) return serial_lambda(previous, current, problem);  // its check throws the message
  return out;
}

}  // namespace dc
