// pgs-colored's solves allocate nothing in steady state but the λ they return: the permuted λ
// pair and the layout's count arrays keep their storage across solves of different sizes. Counts
// the process's heap allocations with the benchmarks' counting allocator (it replaces malloc and
// friends in this test executable), except under the sanitizers, which replace them themselves.
#include <gtest/gtest.h>

#include "dc/lcp/pgs_colored.hpp"
#include "lcp/solver_test_problems.hpp"

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define DC_COUNT_ALLOCATIONS 1
#include "../../../benchmarks/micro/counting_malloc.hpp"
#endif

namespace dc {
namespace {

TEST(PgsColoredAllocations, SteadyStateSolvesAllocateOnlyTheReturnedLambda) {
#if !defined(DC_COUNT_ALLOCATIONS)
  GTEST_SKIP() << "the sanitizers replace the allocator";
#else
  test::TestRng rng(83);
  // Two contact counts on the same bodies in turn, as a World's steps have: the permuted λ's length
  // and the colour count change every solve.
  const LcpProblem big = test::random_contact(200, 700, true, rng, 0.5, 4);
  const LcpProblem small = test::random_contact(200, 300, true, rng, 0.5, 4);
  PgsColoredDef def;
  def.threads = 1;
  const auto solver = make_pgs_colored(def);
  SolverOptions o;
  o.max_sweeps = 5;
  o.record_theta = false;
  const Eigen::VectorXd l_big = Eigen::VectorXd::Zero(big.rows()), l_small = Eigen::VectorXd::Zero(small.rows());
  for (int k = 0; k < 3; ++k) {  // warm: every buffer reaches its size
    (void)solver->solve(big, l_big, o);
    (void)solver->solve(small, l_small, o);
  }
  constexpr int kSolves = 10;
  long allocations = 0;
  for (int k = 0; k < kSolves; ++k) {
    const LcpProblem& p = k % 2 == 0 ? big : small;
    const Eigen::VectorXd& l = k % 2 == 0 ? l_big : l_small;
    const long before = bench::AllocationCounter::count();
    bench::AllocationCounter::start();
    SolveResult r = solver->solve(p, l, o);
    bench::AllocationCounter::stop();
    allocations += bench::AllocationCounter::count() - before;
    ASSERT_EQ(r.lambda.size(), p.rows());
    ASSERT_TRUE(r.message.empty()) << r.message;  // packed, not handed to "pgs"
  }
  EXPECT_LE(allocations, kSolves) << "allocations in " << kSolves << " solves (one each: the returned λ)";
#endif
}

}  // namespace
}  // namespace dc
