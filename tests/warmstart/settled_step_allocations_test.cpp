// A step by the public stages allocates nothing once its storage has grown to the problem:
// collide, assemble (LcpProblem's vectors and J's row index keep their capacity), the builtin
// warm start into a KeptVector the caller keeps (WarmStarter::initial_guess_into), the solve
// into kept storage (LcpSolver::solve_into: pgs-colored writes λ in place; its threaded sweeps
// keep their team and region scratch) and integrate. Also while the row count changes, as long
// as it stays within what the storage held before. The allocations are counted by replacing
// the process's malloc family (benchmarks/micro/counting_malloc.hpp; not in sanitizer builds,
// whose runtimes replace the same functions).
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "dc/core/work_team.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/warmstart/warm_starter.hpp"

#ifdef DC_COUNT_ALLOCATIONS
#include "counting_malloc.hpp"
#endif

namespace dc {
namespace {

#ifdef DC_COUNT_ALLOCATIONS
using bench::AllocationCounter;

/// Allocations made by f (counting on only around it).
template <class F>
long allocations_of(F&& f) {
  const long a = AllocationCounter::count();
  AllocationCounter::start();
  f();
  AllocationCounter::stop();
  return AllocationCounter::count() - a;
}

/// Steps w by its public stages with storage kept across steps; allocations per step.
struct KeptStepper {
  KeptVector guess, lambda;
  SolveResult result;
  std::unique_ptr<WarmStarter> builtin = default_warm_starters().make("builtin");
  long step(World& w, LcpSolver& solver, const SolverOptions& o) {
    return allocations_of([&] {
      w.collide();
      w.assemble();
      builtin->initial_guess_into(StepView{w, nullptr}, guess);
      solver.solve_into(w.problem(), guess, o, lambda, result);
      w.integrate(lambda);
    });
  }
};

/// Steps of a settled pile whose bodies are then set back to where they were while the pile
/// was still falling: its row count changes from step to step (mostly growing again) while it
/// stays below the settled pile's, which the kept storage held. Every such step allocates
/// nothing. `solver` runs one or two threads.
void expect_no_allocation_within_capacity(LcpSolver& solver) {
  WorldDef def = stress::scaled_seed_pile(300);
  SolverOptions o;
  o.max_sweeps = 20;
  o.record_theta = false;
  World falling(def);
  for (int s = 0; s < 60; ++s) falling.step(solver, o, World::WarmStart::PreviousLambda);
  World w(def);
  KeptStepper kept;
  int most_rows = 0;
  for (int s = 0; s < 400; ++s) {  // settles: the storage grows to the pile's rows
    kept.step(w, solver, o);
    most_rows = std::max(most_rows, w.problem().rows());
  }
  w.bodies() = falling.bodies();  // (copy-assigned: the body arrays keep their storage)
  for (int s = 0; s < 3; ++s) kept.step(w, solver, o);  // the contacts of the falling state
  int previous_rows = w.problem().rows(), changed = 0, grew = 0;
  for (int s = 0; s < 40; ++s) {
    const long allocations = kept.step(w, solver, o);
    const int rows = w.problem().rows();
    ASSERT_EQ(kept.lambda.size(), rows);
    ASSERT_EQ(kept.result.lambda.size(), 0);  // (solve_into leaves λ in `lambda` only)
    if (rows <= most_rows) {
      EXPECT_EQ(allocations, 0) << "step " << s << ": " << rows << " rows (" << previous_rows << " before, at most "
                                << most_rows << " held)";
      changed += rows != previous_rows;
      grew += rows > previous_rows;
    }
    previous_rows = rows;
  }
  EXPECT_GE(changed, 10);  // the row count changed from step to step,
  EXPECT_GE(grew, 5);      // growing on many of them
}
#endif

TEST(SettledStepAllocations, StepsAllocateNothingWhileTheRowsFitTheKeptStorage) {
#ifndef DC_COUNT_ALLOCATIONS
  GTEST_SKIP() << "allocation counting is off in sanitizer builds";
#else
  const auto solver = make_solver("pgs-colored");
  expect_no_allocation_within_capacity(*solver);
#endif
}

TEST(SettledStepAllocations, StepsWithATwoThreadSolveAllocateNothingWhileTheRowsFitTheKeptStorage) {
#ifndef DC_COUNT_ALLOCATIONS
  GTEST_SKIP() << "allocation counting is off in sanitizer builds";
#else
  PgsColoredDef def;
  def.threads = 2;
  def.min_batches_per_thread = 0;  // every solve on both threads
  const auto solver = make_pgs_colored(def);
  ASSERT_TRUE(solver->threads_forced());
  expect_no_allocation_within_capacity(*solver);
#endif
}

TEST(SettledStepAllocations, TwoThreadWorldStepsAllocateOnlyTheReportWhileTheRowsFitTheKeptStorage) {
#ifndef DC_COUNT_ALLOCATIONS
  GTEST_SKIP() << "allocation counting is off in sanitizer builds";
#else
  // World::step with forced 2-thread pgs-colored: collide's job lists and their merge, the
  // assembly's jobs, the warm start and the solve all run on the team. As in
  // expect_no_allocation_within_capacity: a settled pile set back to a falling state, whose
  // rows stay within what the kept storage held; a step then allocates only the report's λ.
  PgsColoredDef pd;
  pd.threads = 2;
  pd.min_batches_per_thread = 0;
  const auto solver = make_pgs_colored(pd);
  ASSERT_TRUE(solver->threads_forced());
  const WorldDef def = stress::scaled_seed_pile(2500);  // ≥ 1024 bodies per thread: threaded stages
  SolverOptions o;
  o.max_sweeps = 20;
  o.record_theta = false;
  World falling(def);
  for (int s = 0; s < 60; ++s) falling.step(*solver, o, World::WarmStart::PreviousLambda);
  World w(def);
  int most_rows = 0;
  for (int s = 0; s < 300; ++s) most_rows = std::max(most_rows, w.step(*solver, o, World::WarmStart::PreviousLambda).rows);
  w.bodies() = falling.bodies();
  for (int s = 0; s < 3; ++s) w.step(*solver, o, World::WarmStart::PreviousLambda);
  std::vector<TeamRunTrace> runs;  // the team's threaded runs (reserved: tracing allocates nothing)
  runs.reserve(100000);
  calling_thread_team().set_trace(&runs);
  int previous_rows = w.problem().rows(), changed = 0, checked = 0;
  for (int s = 0; s < 40; ++s) {
    const std::size_t runs0 = runs.size();
    int rows = 0;
    const long allocations = allocations_of([&] { rows = w.step(*solver, o, World::WarmStart::PreviousLambda).rows; });
    EXPECT_GE(runs.size() - runs0, 4U) << "step " << s << " ran its stages serially";
    if (rows <= most_rows && rows > 0) {
      EXPECT_EQ(allocations, 1) << "step " << s << ": " << rows << " rows (" << previous_rows << " before, at most "
                                << most_rows << " held)";
      changed += rows != previous_rows;
      ++checked;
    }
    previous_rows = rows;
  }
  calling_thread_team().set_trace(nullptr);
  EXPECT_GE(checked, 30);
  EXPECT_GE(changed, 10);  // the row count changed from step to step
#endif
}

TEST(SettledStepAllocations, SolveIntoEqualsSolve) {
  World w(stress::scaled_seed_pile(100));
  for (const char* name : {"pgs-colored", "pgs"}) {
    const auto solver = make_solver(name);
    SolverOptions o;
    o.max_sweeps = 10;
    for (int s = 0; s < 50; ++s) w.step(*solver, o, World::WarmStart::PreviousLambda);
    w.collide();
    w.assemble();
    const auto builtin = default_warm_starters().make("builtin");
    const Eigen::VectorXd guess = builtin->initial_guess(StepView{w, nullptr});
    const SolveResult r = solver->solve(w.problem(), guess, o);
    KeptVector lambda = Eigen::VectorXd::Constant(7, 3.0);  // a stale size and values
    SolveResult into;
    solver->solve_into(w.problem(), guess, o, lambda, into);
    ASSERT_EQ(lambda.size(), r.lambda.size()) << name;
    EXPECT_TRUE((lambda.array() == r.lambda.array()).all()) << name;
    EXPECT_EQ(into.status, r.status) << name;
    EXPECT_EQ(into.sweeps, r.sweeps) << name;
    EXPECT_EQ(into.residual, r.residual) << name;
    EXPECT_EQ(into.theta, r.theta) << name;
    w.integrate(lambda);
  }
}

TEST(SettledStepAllocations, GuessIntoEqualsInitialGuess) {
  World w(stress::scaled_seed_pile(100));
  const auto solver = make_solver("pgs-colored");
  SolverOptions o;
  o.max_sweeps = 10;
  for (int s = 0; s < 50; ++s) w.step(*solver, o, World::WarmStart::PreviousLambda);
  w.collide();
  w.assemble();
  const auto builtin = default_warm_starters().make("builtin");
  KeptVector into = Eigen::VectorXd::Constant(3, 7.0);  // a stale size and values
  builtin->initial_guess_into(StepView{w, nullptr}, into);
  const Eigen::VectorXd g = builtin->initial_guess(StepView{w, nullptr});
  ASSERT_EQ(into.size(), g.size());
  EXPECT_TRUE((into.array() == g.array()).all());
}

}  // namespace
}  // namespace dc
