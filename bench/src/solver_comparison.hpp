#pragma once
// Private to the runner (bench_runner.cpp): the solver comparison of one evaluated step
// (docs/bench.md "Solver comparison"). For every (solver, starter) pair it traces the accuracy
// against time from the starter's λ⁰ until the target R, and times a solve to the run's θ
// tolerance. Each pair has its own two solver objects (trace, timed), so a solver that keeps
// state across solves (newton-sparse's symbolic analysis) sees the sequence of steps a simulator
// would show it, and the timed solve never profits from the trace's work on the same step.
#include <memory>
#include <vector>

#include "dc/bench/bench_results.hpp"
#include "dc/lcp/lcp_solver.hpp"

namespace dc::bench {

/// max_i m_i |g| [N] over the bodies with finite mass of the LCP (masses from p.inv_mass), 1 N
/// when there is none or g = 0: the scale the accuracy target R is relative to.
double weight_scale(const LcpProblem& p, Vec2 gravity);

/// Checkpoints of the accuracy trace: every iteration up to 20, then steps of ~3 % up to `cap`.
std::vector<int> accuracy_checkpoints(int cap);

class SolverComparison {
 public:
  /// Makes the solvers (unknown names: ConfigError) and the pair records in `r.pairs`.
  SolverComparison(const BenchOptions& o, BenchResults& r);

  /// Runs every solver from starter `starter`'s guess λ⁰ (its warm start took `warmstart_ms`)
  /// on the step's LCP `p` and appends to the pairs of that starter.
  void run(const LcpProblem& p, Vec2 gravity, std::size_t starter, std::uint64_t seed, const Eigen::VectorXd& lambda0,
           double warmstart_ms);

 private:
  const BenchOptions& o_;
  BenchResults& r_;
  /// Per pair (index as r.pairs): the solver of the trace and of the timed solve.
  std::vector<std::unique_ptr<LcpSolver>> trace_, timed_;
};

}  // namespace dc::bench
