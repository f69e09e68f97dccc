// "pgs-colored" on several threads: the batches packed by whichever thread takes them (dynamic
// schedule, Δu⁰ = M⁻¹Jᵀλ⁰Δt overlapped on one thread) and the natural residual's rows on threads
// are bit-identical to the serial forms, so a solve gives the same λ, θ, sweeps and residual for
// every thread count and on every rerun.
#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "dc/core/work_team.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/engine/world.hpp"
#include "lcp/solver_test_problems.hpp"
#include "engine/fixed_sweeps.hpp"
#include "pgs_colored_kernels.hpp"
#include "solvers/pgs_colored/pgs_colored_batch.hpp"
#include "solvers/pgs_colored/pgs_colored_products.hpp"
#include "solvers/pgs_colored/thread_pacer.hpp"
#include "bytes_equal.hpp"

namespace dc {
namespace {

SolverOptions sweeps(int k) { return test::fixed_sweeps(k); }

SolveResult solve_on(const LcpProblem& p, const Eigen::VectorXd& l0, int threads, int k) {
  PgsColoredDef d;
  d.threads = threads;
  d.min_batches_per_thread = 0;  // thread even the small test problems
  return make_pgs_colored(d)->solve(p, l0, sweeps(k));
}

/// The settled seed-family pile (n circles) after `steps` steps of pgs.
LcpProblem pile_problem(int bodies, int steps, BodyOrder order = BodyOrder::Creation) {
  WorldDef def = default_world_def();
  def.bodies.order = order;
  def.bodies.count = bodies;
  const double side = 30.0 * std::sqrt(bodies / 100.0);
  def.world.width = def.world.height = side;
  def.bodies.mean = {side / 2, side / 2};
  def.bodies.sigma = 4.65 * std::sqrt(bodies / 100.0);
  World world(def);
  const auto pgs = make_solver("pgs");
  SolverOptions o = sweeps(100);
  o.record_theta = false;
  for (int k = 0; k < steps; ++k) world.step(*pgs, o);
  world.collide();
  return world.assemble();
}

int bodies_of(const LcpProblem& p) { return static_cast<int>((p.J.cols() + 2) / 3); }

TEST(PgsColoredThreads, ProductsAreThoseOfTheSerialForms) {
  test::TestRng rng(22);
  const LcpProblem p = test::random_contact(40, 120, true, rng, 0.5, 4);
  Eigen::VectorXd l(p.rows());
  for (int i = 0; i < p.rows(); ++i) l[i] = rng.uniform(-1, 3);
  const Eigen::VectorXd jt = p.J.transpose() * l;  // the serial form (lcp_problem.cpp)
  std::vector<double> du(static_cast<size_t>(colored::kStride) * (bodies_of(p) + 1), -1.0);
  Eigen::VectorXd scratch;
  colored::velocity_change(p, l, bodies_of(p), du.data(), scratch);
  for (int c = 0; c < jt.size(); ++c) {
    const double serial = p.inv_mass[c] * jt[c] * p.dt;
    EXPECT_EQ(0, std::memcmp(&serial, &du[static_cast<size_t>(colored::kStride * (c / 3) + c % 3)], sizeof serial))
        << "column " << c;
  }
  for (int k = 0; k <= bodies_of(p); ++k) EXPECT_EQ(du[static_cast<size_t>(colored::kStride * k + 3)], 0.0);
  const double serial = natural_residual(p, l);
  for (int threads : {1, 2, 3, 7}) {
    bool finite = false;
    const double r = colored::natural_residual(p, l, threads, scratch, finite);
    EXPECT_TRUE(finite);
    EXPECT_EQ(0, std::memcmp(&r, &serial, sizeof r)) << threads << " threads: " << r << " vs " << serial;
  }
  Eigen::VectorXd bad = l;
  bad[3] = std::numeric_limits<double>::quiet_NaN();
  bool finite = true;
  EXPECT_EQ(colored::natural_residual(p, bad, 2, scratch, finite), natural_residual(p, bad));
  EXPECT_FALSE(finite);
}

/// The residual's M⁻¹JᵀλΔt by blocks of bodies on threads: the serial form's bits (±0 included:
/// −0 entries in λ) on random problems, a pile and rows stored out of body order.
TEST(PgsColoredThreads, TransposeProductByBodyBlocksIsTheSerialOne) {
  test::TestRng rng(31);
  std::vector<LcpProblem> problems;
  problems.push_back(test::random_contact(40, 120, true, rng, 0.5, 4));
  problems.push_back(test::random_contact(7, 30, false, rng));
  problems.push_back(pile_problem(60, 40));
  for (const LcpProblem& p : problems) {
    Eigen::VectorXd l(p.rows());
    for (int i = 0; i < p.rows(); ++i) l[i] = i % 5 == 0 ? -0.0 : rng.uniform(-1, 3);
    Eigen::VectorXd serial = p.J.transpose() * l;  // lcp_problem.cpp's velocity_change
    for (int c = 0; c < serial.size(); ++c) serial[c] = p.inv_mass[c] * serial[c] * p.dt;
    for (int threads : {1, 2, 3, 7, 64}) {
      Eigen::VectorXd du = Eigen::VectorXd::Constant(3, 5.0);
      colored::scaled_transpose_product(p, l, threads, du);
      ASSERT_EQ(du.size(), serial.size());
      EXPECT_TRUE(test::bytes_equal(du, serial)) << threads << " threads, " << p.rows() << " rows";
    }
  }
}

TEST(PgsColoredThreads, RandomProblemsGiveTheSameBitsOnEveryThreadCount) {
  for (const bool friction : {false, true}) {
    for (uint64_t seed = 1; seed <= 2; ++seed) {
      test::TestRng rng(seed);
      const LcpProblem p = test::random_contact(60, 150, friction, rng, 0.5, 4);
      Eigen::VectorXd l0(p.rows());
      for (int i = 0; i < p.rows(); ++i) l0[i] = rng.uniform(-1, 3);
      for (int k : {1, 8}) {
        const SolveResult one = solve_on(p, l0, 1, k);
        ASSERT_EQ(one.status, SolveStatus::SweepLimit) << one.message;
        const double serial = natural_residual(p, one.lambda);
        EXPECT_EQ(0, std::memcmp(&one.residual, &serial, sizeof serial));
        for (int threads : {2, 3, 7}) {
          const std::string what = std::to_string(threads) + " threads, seed " + std::to_string(seed);
          const SolveResult r = solve_on(p, l0, threads, k);
          test::expect_same_bits(one, r, what);
          if (threads == 2) test::expect_same_bits(r, solve_on(p, l0, threads, k), what + ", rerun");
        }
      }
    }
  }
}

TEST(PgsColoredThreads, PileGivesTheSameBitsOnEveryThreadCount) {
  const LcpProblem p = pile_problem(400, 60);
  const SolveResult one = solve_on(p, Eigen::VectorXd(), 1, 30);
  const double serial = natural_residual(p, one.lambda);
  EXPECT_EQ(0, std::memcmp(&one.residual, &serial, sizeof serial));
  for (int threads : {2, 3, 7}) {
    test::expect_same_bits(one, solve_on(p, Eigen::VectorXd(), threads, 30), std::to_string(threads) + " threads");
    test::expect_same_bits(solve_on(p, one.lambda, 1, 0), solve_on(p, one.lambda, threads, 0),
                     std::to_string(threads) + " threads, 0 sweeps");
  }
}

/// The parallel colouring (contact_coloring.hpp "Threads") with small chunks, so that the pile's
/// contacts fall into many chunks: λ, θ and residual of whole solves bit-equal for 1, 2, 3 and 7
/// threads, on two successive problems (the second reuses the first's colours) and a repeat.
TEST(PgsColoredThreads, ChunkedColouringGivesTheSameBitsOnEveryThreadCount) {
  const LcpProblem first = pile_problem(400, 60, BodyOrder::Morton), second = pile_problem(400, 61, BodyOrder::Morton);
  ASSERT_GT(first.constraints.size(), 6 * 16);  // ≥ 6 chunks
  auto run = [&](int threads) {
    PgsColoredDef d;
    d.threads = threads;
    d.min_batches_per_thread = 0;
    d.color_chunk = 16;
    const auto solver = make_pgs_colored(d);
    std::vector<SolveResult> r;
    for (const LcpProblem* p : {&first, &second, &second}) r.push_back(solver->solve(*p, Eigen::VectorXd(), sweeps(25)));
    return r;
  };
  const std::vector<SolveResult> one = run(1);
  for (const SolveResult& r : one) EXPECT_EQ(r.status, SolveStatus::SweepLimit) << r.message;
  for (int threads : {2, 3, 7}) {
    const std::vector<SolveResult> r = run(threads);
    for (size_t k = 0; k < r.size(); ++k)
      test::expect_same_bits(one[k], r[k], std::to_string(threads) + " threads, solve " + std::to_string(k));
  }
}

TEST(PgsColoredThreads, RowsStoredOutOfBodyOrderGiveTheSameBits) {
  // A row whose higher body's entries are stored before the lower body's (valid storage for the
  // InnerIterator, never produced by Eigen's own assembly): the products follow the storage
  // order as Eigen's do, and every thread count gives the 1-thread result.
  test::TestRng rng(23);
  LcpProblem p = test::random_contact(30, 60, true, rng);
  int row = -1;
  for (const ContactConstraint& k : p.constraints)
    if (k.has_body_a()) {
      row = k.normal_row;
      break;
    }
  ASSERT_GE(row, 0);
  int* inner = p.J.innerIndexPtr();
  double* value = p.J.valuePtr();
  const int b = p.J.outerIndexPtr()[row], e = p.J.outerIndexPtr()[row + 1];
  ASSERT_EQ(e - b, 6);
  for (int q = 0; q < 3; ++q) {
    std::swap(inner[b + q], inner[b + 3 + q]);
    std::swap(value[b + q], value[b + 3 + q]);
  }
  const SolveResult one = solve_on(p, Eigen::VectorXd(), 1, 20);
  const double serial = natural_residual(p, one.lambda);
  EXPECT_EQ(0, std::memcmp(&one.residual, &serial, sizeof serial));
  for (int threads : {2, 7}) test::expect_same_bits(one, solve_on(p, Eigen::VectorXd(), threads, 20), std::to_string(threads) + " threads");
}

TEST(PgsColoredThreads, CheckpointsToleranceAndCallbackErrorsInTheThreadedSweepLoop) {
  // The threaded sweeps run in one parallel region with the driver on thread 0: checkpoints,
  // the tolerance stop and θ must be those of one thread, and a callback's exception must leave
  // the region and reach the caller.
  const LcpProblem p = pile_problem(400, 60);
  auto run = [&](int threads, double tol, std::vector<Eigen::VectorXd>& seen) {
    PgsColoredDef d;
    d.threads = threads;
    d.min_batches_per_thread = 0;
    SolverOptions o = sweeps(200);
    o.tolerance = tol;
    o.checkpoints = {2, 7};
    o.on_checkpoint = [&](int, const Eigen::VectorXd& l) { seen.push_back(l); };
    return make_pgs_colored(d)->solve(p, Eigen::VectorXd(), o);
  };
  for (const double tol : {0.0, 1e-6}) {
    std::vector<Eigen::VectorXd> seen_one;
    const SolveResult one = run(1, tol, seen_one);
    ASSERT_EQ(seen_one.size(), 2u);
    for (int threads : {2, 3, 7}) {
      std::vector<Eigen::VectorXd> seen;
      const std::string what = std::to_string(threads) + " threads, tolerance " + std::to_string(tol);
      test::expect_same_bits(one, run(threads, tol, seen), what);
      ASSERT_EQ(seen.size(), seen_one.size()) << what;
      for (size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen[k], seen_one[k]) << what << ", checkpoint " << k;
    }
  }
  PgsColoredDef d;
  d.threads = 2;
  d.min_batches_per_thread = 0;
  SolverOptions o = sweeps(20);
  o.checkpoints = {5};
  o.on_checkpoint = [](int, const Eigen::VectorXd&) { throw std::runtime_error("stop here"); };
  EXPECT_THROW((void)make_pgs_colored(d)->solve(p, Eigen::VectorXd(), o), std::runtime_error);
}

TEST(PgsColoredThreads, SmallProblemsStayOnOneThread) {
  using colored::threads_for;
  // micro_step's 1,000-body pile: about 100 batches in 6 colour ranges, fewer than 32 per thread.
  EXPECT_EQ(1, threads_for(2, 32, 100, 6));
  // Its 10,000-body pile: about 770 batches in 6 ranges.
  EXPECT_EQ(2, threads_for(2, 32, 770, 6));
  EXPECT_EQ(1, threads_for(4, 32, 3000, 30));  // more threads need more batches per range
  EXPECT_EQ(1, threads_for(1, 0, 3000, 7));    // one thread asked for
  EXPECT_EQ(2, threads_for(2, 0, 1, 7));       // 0: every problem on the threads
  EXPECT_EQ(2, threads_for(2, 32, 64, 0));     // no ranges yet: counted as one
  // The solver's default threshold keeps the threads' waits out of small problems.
  EXPECT_EQ(1, threads_for(2, PgsColoredDef{}.min_batches_per_thread, 100, 6));
}

TEST(PgsColoredThreads, PacerKeepsThreadsOnlyWhileTheyPay) {
  colored::ThreadPacer pacer;
  ASSERT_TRUE(pacer.threaded_next());  // the first solve tries the threads
  pacer.record(true, 1.0, 1.0);
  ASSERT_FALSE(pacer.threaded_next());  // then one serial solve to compare with
  pacer.record(false, 1.0, 1.0);
  // Threads at half the serial time: kept, with a serial probe after every kRefresh solves.
  int serial = 0;
  for (int k = 0; k < 4 * (colored::ThreadPacer::kRefresh + 1); ++k) {
    const bool threaded = pacer.threaded_next();
    serial += threaded ? 0 : 1;
    pacer.record(threaded, threaded ? 0.5 : 1.0, 1.0);
  }
  EXPECT_EQ(4, serial);
  // Threads slower than serial (the other core busy): serial solves, with threaded probes
  // 1, 2, 4, … kMaxSkip solves apart.
  std::vector<int> gaps;
  int gap = 0;
  for (int k = 0; k < 400; ++k) {
    const bool threaded = pacer.threaded_next();
    if (threaded) {
      gaps.push_back(gap);
      gap = 0;
    } else {
      ++gap;
    }
    pacer.record(threaded, threaded ? 2.0 : 1.0, 1.0);
  }
  ASSERT_GE(gaps.size(), 8u);
  EXPECT_EQ(1, gaps[1]);
  EXPECT_EQ(2, gaps[2]);
  EXPECT_EQ(4, gaps[3]);
  EXPECT_EQ(colored::ThreadPacer::kMaxSkip, gaps.back());
  // Paying again: the threads are kept from the next probe on.
  for (int k = 0; k < 200 && !pacer.threaded_next(); ++k) pacer.record(false, 1.0, 1.0);
  ASSERT_TRUE(pacer.threaded_next());
  pacer.record(true, 0.5, 1.0);
  EXPECT_TRUE(pacer.threaded_next());
}

/// Led by its caller (World::step), a paced solver threads every solve it is not held on, the
/// second too (its own pacer would run that one serially to compare), and a held solve is
/// serial; either gives the serial solver's bits.
TEST(PgsColoredThreads, LedSolvesFollowTheCaller) {
  const LcpProblem p = pile_problem(300, 20);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
  PgsColoredDef one, two;
  two.threads = 2;
  two.min_batches_per_thread = 1;
  const auto s1 = make_pgs_colored(one), s2 = make_pgs_colored(two);
  ASSERT_EQ(2, s2->thread_capacity());
  const SolveResult serial = s1->solve(p, zero, sweeps(30));
  std::vector<TeamRunTrace> trace;
  calling_thread_team().set_trace(&trace);
  s2->lead_threads(true);
  std::vector<size_t> runs;
  for (const bool held : {false, false, true}) {
    s2->hold_threads(held);
    const size_t before = trace.size();
    test::expect_same_bits(serial, s2->solve(p, zero, sweeps(30)), held ? "held" : "led");
    runs.push_back(trace.size() - before);
  }
  s2->hold_threads(false);
  s2->lead_threads(false);
  calling_thread_team().set_trace(nullptr);
  EXPECT_GT(runs[0], 0u);
  EXPECT_GT(runs[1], 0u);
  EXPECT_EQ(0u, runs[2]);
}

/// A solver that paces its threads (min_batches_per_thread > 0) runs some solves threaded and
/// some serially: a sequence of solves gives the bits of the serial solver's sequence.
TEST(PgsColoredThreads, PacedSolvesGiveTheSameBitsAsOneThread) {
  const LcpProblem a = pile_problem(300, 20), b = pile_problem(300, 24);
  PgsColoredDef one, two;
  two.threads = 2;
  two.min_batches_per_thread = 1;
  const auto s1 = make_pgs_colored(one), s2 = make_pgs_colored(two);
  for (int k = 0; k < 8; ++k) {
    const LcpProblem& p = k % 3 == 2 ? b : a;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
    test::expect_same_bits(s1->solve(p, zero, sweeps(30)), s2->solve(p, zero, sweeps(30)), "solve " + std::to_string(k));
  }
}

}  // namespace
}  // namespace dc
