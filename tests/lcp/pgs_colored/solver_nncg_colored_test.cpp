// "nncg-colored" (pgs_colored.hpp, pgs_colored.cpp with nncg_momentum.hpp): nncg's momentum on
// pgs-colored's colour-ordered sweeps. Relationships: lemke's (and the dense newton's) contact
// velocities where they are unique; without the momentum pgs-colored's iterates bit for bit;
// fewer sweeps than pgs-colored on a deep pile (the momentum's β rule at work); the per-chunk
// hook sees the iterates plain runs return after as many sweeps; bit-equal reruns, on threads
// too; prox-newton's colored lead reaches the target.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/solver_common.hpp"
#include "solvers/solvers.hpp"

namespace dc {
namespace {

SolverOptions to_tolerance(double tol, int cap, bool theta = false) {
  SolverOptions o;
  o.max_sweeps = cap;
  o.tolerance = tol;
  o.record_theta = theta;
  return o;
}

SolverOptions sweeps_only(int sweeps) { return to_tolerance(0.0, sweeps, true); }

/// λ, θ, sweeps, status and residual equal to the bit.
void expect_same_bits(const SolveResult& a, const SolveResult& b, const std::string& what) {
  ASSERT_EQ(a.lambda.size(), b.lambda.size()) << what;
  EXPECT_EQ(0, std::memcmp(a.lambda.data(), b.lambda.data(), sizeof(double) * static_cast<size_t>(a.lambda.size())))
      << what;
  ASSERT_EQ(a.theta.size(), b.theta.size()) << what;
  // memcmp's pointers must not be null even for zero bytes (UBSan stops on it): solvers that
  // record no θ (prox-newton) hand out an empty vector.
  if (!a.theta.empty()) {
    EXPECT_EQ(0, std::memcmp(a.theta.data(), b.theta.data(), sizeof(double) * a.theta.size())) << what;
  }
  EXPECT_EQ(a.sweeps, b.sweeps) << what;
  EXPECT_EQ(a.status, b.status) << what;
  EXPECT_EQ(0, std::memcmp(&a.residual, &b.residual, sizeof(double))) << what;
}

/// The problems the colour kernels cover (no "ran nncg" fallback): frictional, frictionless and
/// mixed, rank-deficient (more rows than body dofs) among them.
std::vector<LcpProblem> problems() {
  std::vector<LcpProblem> out;
  test::TestRng rng(5100);
  out.push_back(test::random_contact(30, 25, true, rng));   // frictional, unique solution
  out.push_back(test::random_contact(10, 60, false, rng));  // 60 rows, rank ≤ 30
  out.push_back(test::random_contact(12, 40, true, rng));   // 80 rows, rank ≤ 36, friction
  out.push_back(test::random_contact(40, 80, true, rng, 0.5, 3));
  out.push_back(test::deep_pile(5, 6, 0.5));
  return out;
}

TEST(SolverNncgColored, IsRegisteredAndRunsTheColourKernels) {
  EXPECT_EQ(make_solver("nncg-colored")->name(), "nncg-colored");
  EXPECT_EQ(to_string(SolverId::parse("nncg-colored")), "nncg-colored");
  for (const LcpProblem& p : problems()) {
    const SolveResult r = make_solver("nncg-colored")->solve(p, {}, sweeps_only(10));
    EXPECT_EQ(r.message.find("ran nncg"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("restart(s) of the CG direction"), std::string::npos) << r.message;
  }
  // Without J: nncg (assembled form), named in the message.
  test::TestRng rng(5101);
  const LcpProblem file = test::without_jacobian(test::random_contact(10, 20, true, rng));
  const SolveResult r = make_solver("nncg-colored")->solve(file, {}, to_tolerance(1e-10, 20000));
  EXPECT_NE(r.message.find("ran nncg"), std::string::npos) << r.message;
  EXPECT_TRUE(stopped_at_tolerance(r.status)) << r.message;
}

// λ is not unique on rank-deficient problems; w = A λ + b is. lemke solves standard LCPs only,
// so the frictional problem (fewer rows than body dofs) is compared with the dense newton; with
// friction and more rows than dofs Coulomb's problem may have several solutions (w included),
// so there the test asks for a solution at the solution target.
TEST(SolverNncgColored, SameContactVelocitiesAsLemkeAndNewton) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 5200);
    const LcpProblem rank_deficient = test::random_contact(10, 60, false, rng);
    const LcpProblem friction = test::random_contact(30, 25, true, rng);
    const LcpProblem deficient_friction = test::random_contact(12, 40, true, rng);
    const SolveResult lemke = make_solver("lemke")->solve(rank_deficient, {}, SolverOptions{});
    ASSERT_EQ(lemke.status, SolveStatus::Converged) << lemke.message;
    const SolveResult a = make_solver("nncg-colored")->solve(rank_deficient, {}, to_tolerance(1e-13, 100000));
    ASSERT_TRUE(stopped_at_tolerance(a.status)) << a.message;
    EXPECT_LE((lcp_velocity(rank_deficient, a.lambda) - lcp_velocity(rank_deficient, lemke.lambda)).cwiseAbs().maxCoeff(),
              1e-6)
        << seed;
    const SolveResult newton = make_solver("newton")->solve(friction, {}, to_tolerance(0.0, 3000));
    ASSERT_EQ(newton.status, SolveStatus::Converged) << newton.message;
    const SolveResult b = make_solver("nncg-colored")->solve(friction, {}, to_tolerance(1e-13, 100000));
    ASSERT_TRUE(stopped_at_tolerance(b.status)) << b.message;
    EXPECT_LE((lcp_velocity(friction, b.lambda) - lcp_velocity(friction, newton.lambda)).cwiseAbs().maxCoeff(), 1e-6)
        << seed;
    const SolveResult c = make_solver("nncg-colored")->solve(deficient_friction, {}, to_tolerance(1e-13, 100000));
    EXPECT_EQ(c.status, SolveStatus::Converged) << seed << ": " << c.message;
  }
}

TEST(SolverNncgColored, WithoutTheMomentumIsPgsColoredBitForBit) {
  NncgColoredDef off;
  off.momentum = false;
  for (PgsColoredKernel k : {PgsColoredKernel::Auto, PgsColoredKernel::Scalar}) {
    off.sweep.kernel = k;
    PgsColoredDef pd;
    pd.kernel = k;
    int i = 0;
    for (const LcpProblem& p : problems()) {
      for (const SolverOptions& o : {sweeps_only(37), to_tolerance(1e-9, 5000, true)}) {
        const SolveResult a = make_nncg_colored(off)->solve(p, {}, o);
        const SolveResult b = make_pgs_colored(pd)->solve(p, {}, o);
        expect_same_bits(a, b, "problem " + std::to_string(i) + " kernel " + to_string(k));
      }
      ++i;
    }
  }
}

TEST(SolverNncgColored, FirstTwoSweepsArePgsColoredSweepsAndTheThirdIsNot) {
  // Sweep 1 sets the direction, sweep 2 the first β, which moves λ only before sweep 3.
  test::TestRng rng(5300);
  const LcpProblem p = test::random_contact(60, 80, true, rng);
  const SolveResult pgs = make_pgs_colored()->solve(p, {}, sweeps_only(2));
  const SolveResult nncg = make_solver("nncg-colored")->solve(p, {}, sweeps_only(2));
  EXPECT_EQ((nncg.lambda - pgs.lambda).cwiseAbs().maxCoeff(), 0.0);
  const SolveResult pgs3 = make_pgs_colored()->solve(p, {}, sweeps_only(3));
  const SolveResult nncg3 = make_solver("nncg-colored")->solve(p, {}, sweeps_only(3));
  EXPECT_GT((nncg3.lambda - pgs3.lambda).cwiseAbs().maxCoeff(), 0.0) << "no momentum applied before sweep 3";
}

TEST(SolverNncgColored, FewerSweepsThanPgsColoredOnADeepPile) {
  const LcpProblem p = test::deep_pile(8, 24, 0.5);
  const SolverOptions o = to_tolerance(1e-4, 30000);  // θ ≤ 1e-4 N, bodies weigh 31 N
  const SolveResult pgs = make_pgs_colored()->solve(p, {}, o);
  const SolveResult nncg = make_solver("nncg-colored")->solve(p, {}, o);
  ASSERT_TRUE(stopped_at_tolerance(nncg.status)) << to_string(nncg.status) << ": " << nncg.message;
  RecordProperty("pgs_colored_sweeps", pgs.sweeps);
  RecordProperty("nncg_colored_sweeps", nncg.sweeps);
  EXPECT_LT(2 * nncg.sweeps, pgs.sweeps) << "pgs-colored " << pgs.sweeps << ", nncg-colored " << nncg.sweeps;
  EXPECT_LT(nncg.residual, 1e-2);
}

TEST(SolverNncgColored, TheHookSeesThePlainRunsIteratesAndStopsWhereAsked) {
  for (const LcpProblem& p : problems()) {
    const auto watched = make_solver("nncg-colored");
    std::vector<int> looks;
    std::vector<Eigen::VectorXd> seen;
    solvers::SweepWatch w;
    w.every = 7;
    w.stop = [&](int k, const Eigen::VectorXd& x) {
      looks.push_back(k);
      seen.push_back(x);
      return looks.size() == 3;
    };
    const SolveResult r = solvers::nncg_colored_solve(*watched, p, {}, sweeps_only(1000), &w);
    ASSERT_EQ(looks, (std::vector<int>{7, 14, 21}));
    EXPECT_EQ(r.sweeps, 21);
    for (std::size_t i = 0; i < looks.size(); ++i) {
      const SolveResult plain = make_solver("nncg-colored")->solve(p, {}, sweeps_only(looks[i]));
      ASSERT_EQ(seen[i].size(), plain.lambda.size());
      EXPECT_EQ(0, std::memcmp(seen[i].data(), plain.lambda.data(), sizeof(double) * seen[i].size())) << looks[i];
    }
    EXPECT_EQ(0, std::memcmp(r.lambda.data(), seen.back().data(), sizeof(double) * r.lambda.size()));
    // A hook that never stops leaves the run as without it; the solver object after a watched
    // solve solves as a fresh one.
    w.stop = [](int, const Eigen::VectorXd&) { return false; };
    expect_same_bits(solvers::nncg_colored_solve(*watched, p, {}, sweeps_only(100), &w),
                     make_solver("nncg-colored")->solve(p, {}, sweeps_only(100)), "never stops");
    expect_same_bits(watched->solve(p, {}, sweeps_only(60)), make_solver("nncg-colored")->solve(p, {}, sweeps_only(60)),
                     "after a watched solve");
  }
  EXPECT_THROW((void)solvers::nncg_colored_solve(*make_pgs_colored(), problems()[0], {}, sweeps_only(1), nullptr),
               InvalidArgument);
}

TEST(SolverNncgColored, CheckpointsSeeThePlainRunsIteratesInRowOrder) {
  // One solver object over problems of different sizes and colourings (the row-order look is
  // rebuilt per solve), pgs-colored and nncg-colored, serial and on threads: the λ a checkpoint
  // sees after sweep k is the λ a plain run of k sweeps returns, bit for bit.
  PgsColoredDef threaded;
  threaded.threads = 2;
  threaded.min_batches_per_thread = 0;
  NncgColoredDef nncg_threaded;
  nncg_threaded.sweep = threaded;
  const std::vector<std::pair<std::unique_ptr<LcpSolver>, std::unique_ptr<LcpSolver>>> pairs = [&] {
    std::vector<std::pair<std::unique_ptr<LcpSolver>, std::unique_ptr<LcpSolver>>> v;
    v.emplace_back(make_solver("nncg-colored"), make_solver("nncg-colored"));
    v.emplace_back(make_solver("pgs-colored"), make_solver("pgs-colored"));
    v.emplace_back(make_nncg_colored(nncg_threaded), make_nncg_colored(nncg_threaded));
    v.emplace_back(make_pgs_colored(threaded), make_pgs_colored(threaded));
    return v;
  }();
  for (const auto& [watched, plain] : pairs) {
    for (const LcpProblem& p : problems()) {
      std::vector<Eigen::VectorXd> seen;
      SolverOptions o = sweeps_only(20);
      o.checkpoints = {1, 6, 20};
      o.on_checkpoint = [&](int, const Eigen::VectorXd& x) { seen.push_back(x); };
      const SolveResult r = watched->solve(p, {}, o);
      ASSERT_EQ(seen.size(), 3u) << watched->name();
      for (std::size_t i = 0; i < seen.size(); ++i) {
        const SolveResult ref = plain->solve(p, {}, sweeps_only(o.checkpoints[i]));
        ASSERT_EQ(seen[i].size(), ref.lambda.size());
        EXPECT_EQ(0, std::memcmp(seen[i].data(), ref.lambda.data(), sizeof(double) * seen[i].size()))
            << watched->name() << " sweep " << o.checkpoints[i] << " rows " << p.rows();
      }
      EXPECT_EQ(0, std::memcmp(r.lambda.data(), seen.back().data(), sizeof(double) * r.lambda.size()));
    }
  }
}

TEST(SolverNncgColored, BitEqualRerunsOnEveryKernelAndOnThreads) {
  std::vector<NncgColoredDef> defs(3);
  defs[1].sweep.kernel = PgsColoredKernel::Scalar;
  defs[2].sweep.threads = 2;
  defs[2].sweep.min_batches_per_thread = 0;  // threads on every problem
  int i = 0;
  for (const LcpProblem& p : problems()) {
    const SolveResult ref = make_solver("nncg-colored")->solve(p, {}, to_tolerance(1e-10, 3000, true));
    for (size_t k = 0; k < defs.size(); ++k) {
      const auto s = make_nncg_colored(defs[k]);
      for (int rerun = 0; rerun < 2; ++rerun)
        expect_same_bits(s->solve(p, {}, to_tolerance(1e-10, 3000, true)), ref,
                         "problem " + std::to_string(i) + " def " + std::to_string(k) + " rerun " + std::to_string(rerun));
    }
    ++i;
  }
}

TEST(SolverNncgColored, ProxNewtonsColoredLeadIsPlainNncgColoredToTheSweepItStopsAt) {
  // A target nncg-colored reaches: the answer is its iterate after the stage's sweeps.
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 3400);
    const LcpProblem p = test::random_contact(40, 80, true, rng);
    SolverOptions o;
    o.max_sweeps = 10000;
    o.tolerance = 1e-6 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
    ProxNewtonDef d;
    d.lead_sweep = ProxLeadSweep::Colored;
    d.probe_sweeps = 0;  // 1.33 rows per velocity unknown: degenerate, where the probe would end the stage
    ProxNewtonSolver s(d);
    const SolveResult r = s.solve(p, {}, o);
    ASSERT_EQ(r.message.rfind("finished by nncg lead stage", 0), 0u) << r.message;
    const SolveResult plain = make_solver("nncg-colored")->solve(p, {}, sweeps_only(s.last_stats().lead_sweeps));
    EXPECT_EQ(0, std::memcmp(r.lambda.data(), plain.lambda.data(), sizeof(double) * r.lambda.size())) << seed;
  }
}

TEST(SolverNncgColored, ProxNewtonsAutoLeadIsColoredFromItsRowThresholdOn) {
  // Auto picks by the problem's rows: at or above lead_colored_rows the answer is the colored
  // lead's bit for bit, below it the natural lead's.
  test::TestRng rng(3401);
  const LcpProblem p = test::random_contact(40, 80, true, rng);
  SolverOptions o;
  o.max_sweeps = 10000;
  o.tolerance = 1e-6 * std::max(1.0, p.b.cwiseAbs().maxCoeff());
  auto solve_with = [&](ProxLeadSweep sweep, int threshold) {
    ProxNewtonDef d;
    d.lead_sweep = sweep;
    d.lead_colored_rows = threshold;
    return ProxNewtonSolver(d).solve(p, {}, o);
  };
  const SolveResult natural = solve_with(ProxLeadSweep::Natural, 0);
  const SolveResult colored = solve_with(ProxLeadSweep::Colored, 0);
  ASSERT_NE(0, std::memcmp(natural.lambda.data(), colored.lambda.data(), sizeof(double) * natural.lambda.size()))
      << "the two leads round alike on this problem: the test cannot tell them apart";
  expect_same_bits(solve_with(ProxLeadSweep::Auto, p.rows()), colored, "auto at the threshold");
  expect_same_bits(solve_with(ProxLeadSweep::Auto, p.rows() + 1), natural, "auto below the threshold");
  ProxNewtonDef bad;
  bad.lead_colored_rows = -1;
  EXPECT_THROW(ProxNewtonSolver{bad}, InvalidArgument);
}

TEST(SolverNncgColored, ProxNewtonWithTheColoredLeadReachesTheTarget) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 5400);
    for (const LcpProblem& p : {test::random_contact(40, 80, true, rng), test::deep_pile(6, 10, 0.5)}) {
      ProxNewtonDef d;
      d.lead_sweep = ProxLeadSweep::Colored;
      ProxNewtonSolver colored(d);
      SolverOptions o;
      o.max_sweeps = 20000;
      const SolveResult r = colored.solve(p, {}, o);
      EXPECT_EQ(r.status, SolveStatus::Converged) << seed << ": " << r.message;
      EXPECT_GT(colored.last_stats().lead_sweeps, 0) << r.message;
      const SolveResult again = colored.solve(p, {}, o);  // the kept colouring: the same answer
      expect_same_bits(again, r, "prox-newton rerun");
    }
  }
}

}  // namespace
}  // namespace dc
