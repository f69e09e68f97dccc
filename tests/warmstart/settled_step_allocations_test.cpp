// A settled pile's step allocates nothing outside the solver: collide, assemble, the builtin
// warm start into storage the caller keeps (WarmStarter::initial_guess_into) and integrate
// reuse their storage while the row count stays. The allocations are counted by replacing the
// process's malloc family (benchmarks/micro/counting_malloc.hpp; not in sanitizer builds,
// whose runtimes replace the same functions). A step whose row count changes resizes the
// problem's Eigen vectors and J's row index (exact-size storage): not asserted here.
#include <gtest/gtest.h>

#include <vector>

#include "dc/engine/stress_scenes.hpp"
#include "dc/lcp/lcp_solver.hpp"
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
#endif

TEST(SettledStepAllocations, StagesOutsideTheSolverAllocateNothingAtASteadyRowCount) {
#ifndef DC_COUNT_ALLOCATIONS
  GTEST_SKIP() << "allocation counting is off in sanitizer builds";
#else
  WorldDef def = stress::scaled_seed_pile(300);
  World w(def);
  const auto solver = make_solver("pgs-colored");
  SolverOptions o;
  o.max_sweeps = 20;
  for (int s = 0; s < 400; ++s) w.step(*solver, o, World::WarmStart::PreviousLambda);  // settles
  const auto builtin = default_warm_starters().make("builtin");
  Eigen::VectorXd guess;
  int previous_rows = -1, steady = 0;
  for (int s = 0; s < 40; ++s) {
    long outside = allocations_of([&] {
      w.collide();
      w.assemble();
      builtin->initial_guess_into(StepView{w, nullptr}, guess);
    });
    const int rows = w.problem().rows();
    ASSERT_EQ(guess.size(), rows);
    const Eigen::VectorXd lambda = solver->solve(w.problem(), guess, o).lambda;
    outside += allocations_of([&] { w.integrate(lambda); });
    if (rows == previous_rows && s > 0) {
      EXPECT_EQ(outside, 0) << "step " << s << " (" << rows << " rows, as the step before)";
      ++steady;
    }
    previous_rows = rows;
  }
  EXPECT_GE(steady, 10);  // the pile is settled: many steps keep their row count
#endif
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
  Eigen::VectorXd into = Eigen::VectorXd::Constant(3, 7.0);  // a stale size and values
  builtin->initial_guess_into(StepView{w, nullptr}, into);
  const Eigen::VectorXd g = builtin->initial_guess(StepView{w, nullptr});
  ASSERT_EQ(into.size(), g.size());
  EXPECT_TRUE((into.array() == g.array()).all());
}

}  // namespace
}  // namespace dc
