#pragma once
// What the peer comparisons (box2d_compare, box2d3_compare) time on our side: the stepping
// thread's CPU time, and the solver's share of it with the rows × sweeps it did.
#include <time.h>

#include <memory>
#include <string>
#include <utility>

#include "dc/lcp/lcp_solver.hpp"

namespace dc::compare {

/// CPU time of the calling thread [s] (CLOCK_THREAD_CPUTIME_ID: other processes on a shared
/// machine do not count).
inline double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Wraps a solver: sums the thread CPU time of its solve calls [s] and the rows × sweeps they
/// did (cpu_s / row_sweeps = the solver's cost per row·pass, set-up included).
class TimedSolver final : public LcpSolver {
 public:
  explicit TimedSolver(std::unique_ptr<LcpSolver> s) : s_(std::move(s)) {}
  [[nodiscard]] std::string name() const override { return s_->name(); }
  [[nodiscard]] bool needs_jacobian() const override { return s_->needs_jacobian(); }
  [[nodiscard]] bool needs_assembled_matrix() const override { return s_->needs_assembled_matrix(); }
  [[nodiscard]] SolveResult solve(const LcpProblem& p, const Eigen::VectorXd& l0, const SolverOptions& o) override {
    const double t0 = thread_cpu_s();
    SolveResult r = s_->solve(p, l0, o);
    cpu_s += thread_cpu_s() - t0;
    row_sweeps += static_cast<double>(p.rows()) * r.sweeps;
    return r;
  }
  double cpu_s = 0, row_sweeps = 0;

 private:
  std::unique_ptr<LcpSolver> s_;
};

}  // namespace dc::compare
