// "pgs-colored" (colour-ordered PGS, AVX-512 lanes, OpenMP): the colouring is valid and
// incremental, the SIMD and the scalar path and every thread count give bit-identical
// iterates, and it converges to the fixed point of "pgs" (another Gauss–Seidel order of the
// same iteration) on random contact problems and on real piles.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "dc/core/error.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/pgs_colored.hpp"
#include "dc/engine/stress_scenes.hpp"
#include "dc/engine/world.hpp"
#include "lcp/solver_test_problems.hpp"
#include "pgs_colored_kernels.hpp"
#include "solvers/pgs_colored/coloring/contact_coloring.hpp"

namespace dc {
namespace {

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

SolverOptions sweeps(int k, double tol = 0.0) {
  SolverOptions o;
  o.max_sweeps = k;
  o.tolerance = tol;
  return o;
}

std::vector<std::uint8_t> all_dynamic(const LcpProblem& p) {
  return std::vector<std::uint8_t>(static_cast<size_t>(p.J.cols() / 3), 1);
}

/// The settled seed-family pile (n circles, box side ∝ √n) after `steps` steps of pgs.
LcpProblem pile_problem(int bodies, int steps) {
  WorldDef def = default_world_def();
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

TEST(ContactColoring, NoColourSharesADynamicBody) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    test::TestRng rng(seed);
    const LcpProblem p = test::random_contact(30, 120, true, rng);
    ContactColorer colorer(false);
    const auto dyn = all_dynamic(p);
    const ContactColoring& c = colorer.color(p.constraints, dyn);
    EXPECT_TRUE(is_valid_coloring(p.constraints, dyn, c));
    EXPECT_EQ(c.overflow, 0);
    EXPECT_GE(c.colors, 2);
  }
  const LcpProblem pile = pile_problem(100, 150);
  ContactColorer colorer;
  const auto dyn = all_dynamic(pile);
  const ContactColoring& c = colorer.color(pile.constraints, dyn);
  EXPECT_TRUE(is_valid_coloring(pile.constraints, dyn, c));
  EXPECT_LE(c.colors, 12);  // ≤ 6 neighbours + 2 walls per circle: greedy needs ≤ 2·8 − 1
}

TEST(ContactColoring, CheckerRejectsASharedBody) {
  ContactConstraints k;
  k.add(0, 1, 0.5);
  k.add(1, 2, 0.5);
  k.add(-1, 2, 0.5);
  ContactColoring c;
  c.colors = 2;
  c.color = {0, 0, 1};  // contacts 0 and 1 share body 1
  const std::vector<std::uint8_t> dyn(3, 1);
  EXPECT_FALSE(is_valid_coloring(k, dyn, c));
  c.color = {0, 1, 0};
  EXPECT_TRUE(is_valid_coloring(k, dyn, c));
  // Body 1 static (M⁻¹ = 0): it does not conflict; walls never do.
  const std::vector<std::uint8_t> dyn1 = {1, 0, 1};
  c.color = {0, 0, 1};
  EXPECT_TRUE(is_valid_coloring(k, dyn1, c));
  ContactColorer colorer(false);
  EXPECT_EQ(colorer.color(k, dyn1).colors, 2);  // contacts 1 and 2 share body 2
}

TEST(ContactColoring, PersistingContactsKeepTheirColours) {
  test::TestRng rng(3);
  const LcpProblem p = test::random_contact(40, 90, true, rng);
  const auto dyn = all_dynamic(p);
  ContactColorer colorer;
  const std::vector<int> first = colorer.color(p.constraints, dyn).color;
  const ContactColoring& again = colorer.color(p.constraints, dyn);
  EXPECT_EQ(again.color, first);
  // Drop the first contact and add one at the end: everything else persists.
  ContactConstraints next;
  for (int c = 1; c < p.constraints.size(); ++c) {
    const ContactConstraint& k = p.constraints[c];
    next.add(k.body_a, k.body_b, k.mu, k.feature);
  }
  next.add(3, 7, 0.5, 99);
  const ContactColoring& inc = colorer.color(next, dyn);
  EXPECT_TRUE(is_valid_coloring(next, dyn, inc));
  int kept = 0;
  for (int c = 1; c < p.constraints.size(); ++c) kept += inc.color[static_cast<size_t>(c - 1)] == first[static_cast<size_t>(c)];
  EXPECT_EQ(inc.reused, p.constraints.size() - 1);
  EXPECT_EQ(kept, p.constraints.size() - 1);
}

class PgsColoredPaths : public ::testing::TestWithParam<bool> {};

TEST_P(PgsColoredPaths, KernelsAndThreadsAreBitEqual) {
  const bool friction = GetParam();
  PgsColoredDef threaded;
  threaded.threads = 2;
  threaded.min_batches_per_thread = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed);
    const LcpProblem p = test::random_contact(60, 150, friction, rng, 0.5, 4);
    Eigen::VectorXd l0(p.rows());
    for (int i = 0; i < p.rows(); ++i) l0[i] = rng.uniform(-1, 3);
    for (int k : {1, 7, 60}) {
      const SolveResult s = make_pgs_colored()->solve(p, l0, sweeps(k));
      ASSERT_EQ(s.status, SolveStatus::SweepLimit) << s.message;
      for (const PgsColoredDef& d : test::pgs_colored_kernel_defs())
        test::expect_bit_equal(s, make_pgs_colored(d)->solve(p, l0, sweeps(k)), to_string(d.kernel));
      test::expect_bit_equal(s, make_pgs_colored(threaded)->solve(p, l0, sweeps(k)), "2 threads");
      test::expect_bit_equal(s, make_pgs_colored()->solve(p, l0, sweeps(k)), "rerun");
    }
  }
}

INSTANTIATE_TEST_SUITE_P(PgsColoredFriction, PgsColoredPaths, ::testing::Values(false, true));

TEST(PgsColored, PileKernelsThreadsBitEqual) {
  const LcpProblem p = pile_problem(400, 60);
  PgsColoredDef threaded;
  threaded.threads = 2;
  threaded.min_batches_per_thread = 0;
  const SolveResult s = make_pgs_colored()->solve(p, Eigen::VectorXd(), sweeps(40));
  for (const PgsColoredDef& d : test::pgs_colored_kernel_defs())
    test::expect_bit_equal(s, make_pgs_colored(d)->solve(p, Eigen::VectorXd(), sweeps(40)), to_string(d.kernel));
  test::expect_bit_equal(s, make_pgs_colored(threaded)->solve(p, Eigen::VectorXd(), sweeps(40)), "2 threads");
}

TEST(PgsColored, ManifoldKernelsThreadsBitEqual) {
  // A pyramid of base 12: 78 boxes, most faces two-point manifolds, several pair batches per
  // colour (full and partial lane groups), friction and frictionless.
  for (double mu : {0.5, 0.0}) {
    const LcpProblem p = test::pyramid_problem(12, 20, mu);
    PgsColoredDef threaded;
    threaded.threads = 2;
    threaded.min_batches_per_thread = 0;
    Eigen::VectorXd l0 = Eigen::VectorXd::Zero(p.rows());
    for (int i = 0; i < p.rows(); ++i) l0[i] = p.is_friction_row(i) ? 0.1 * (i % 3 - 1) : 0.5 * (i % 4);
    for (int k : {1, 5, 40}) {
      const SolveResult s = make_pgs_colored()->solve(p, l0, sweeps(k));
      ASSERT_EQ(s.status, SolveStatus::SweepLimit) << s.message;
      for (const PgsColoredDef& d : test::pgs_colored_kernel_defs())
        test::expect_bit_equal(s, make_pgs_colored(d)->solve(p, l0, sweeps(k)), to_string(d.kernel));
      test::expect_bit_equal(s, make_pgs_colored(threaded)->solve(p, l0, sweeps(k)), "2 threads");
    }
  }
}

TEST(PgsColored, ManifoldsReachTheFixedPointOfPgs) {
  // Frictionless: the LCP is a convex QP, which both Gauss–Seidel orders solve.
  const LcpProblem p = test::pyramid_problem(8, 30, 0.0);
  const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(20000, 1e-10));
  const SolveResult c = make_solver("pgs-colored")->solve(p, Eigen::VectorXd(), sweeps(20000, 1e-10));
  EXPECT_TRUE(c.message.empty()) << c.message;  // no fallback to pgs
  EXPECT_LE(a.residual, 1e-6);
  EXPECT_LE(c.residual, 1e-6);
  const Eigen::VectorXd ua = p.inv_mass.asDiagonal() * (p.J.transpose() * a.lambda) * p.dt;
  const Eigen::VectorXd uc = p.inv_mass.asDiagonal() * (p.J.transpose() * c.lambda) * p.dt;
  EXPECT_LE(max_abs(ua - uc), 1e-6);
}

TEST(PgsColored, TwentyBoxStackStandsAsWithPgs) {
  // The two-point manifold block in the colour kernels: 100 sweeps with the builtin warm start
  // keep the 20-box stack straight for 10 s, as they do for pgs (ShapePhysics test).
  World w(stress::box_stack(20, {1.0, 1.0}));
  const std::vector<Vec2> start = w.bodies().position;
  const auto solver = make_solver("pgs-colored");
  SolverOptions o = sweeps(100, 1e-9);
  o.record_theta = false;
  double drift = 0;
  for (int s = 0; s < 1000; ++s) {
    w.step(*solver, o, World::WarmStart::PreviousLambda);
    for (size_t k = 0; k < start.size(); ++k) drift = std::max(drift, std::abs(w.bodies().position[k].x - start[k].x));
  }
  EXPECT_LT(drift, 0.01);  // 1 % of the width
  EXPECT_NEAR(w.bodies().position[19].y, start[19].y, 0.1);
}

TEST(PgsColored, ReusedBuffersGiveTheResultOfAFreshSolver) {
  // The solver keeps its batches, λ and Δu buffers between solves: a smaller problem after a
  // larger one (stale lanes, stale padding) must give what a fresh solver gives, per kernel.
  test::TestRng rng(11);
  const LcpProblem big = test::random_contact(80, 200, true, rng, 0.5, 4);
  const LcpProblem small = test::random_contact(20, 30, true, rng, 0.5, 4);
  const LcpProblem frictionless = test::random_contact(25, 33, false, rng, 0.5, 4);
  for (PgsColoredDef d : test::pgs_colored_kernel_defs()) {
    d.reuse_colors = false;  // the same colouring as a fresh solver's
    const auto reused = make_pgs_colored(d);
    (void)reused->solve(big, Eigen::VectorXd(), sweeps(5));
    test::expect_bit_equal(reused->solve(small, Eigen::VectorXd(), sweeps(9)),
                     make_pgs_colored(d)->solve(small, Eigen::VectorXd(), sweeps(9)), to_string(d.kernel));
    test::expect_bit_equal(reused->solve(frictionless, Eigen::VectorXd(), sweeps(9)),
                     make_pgs_colored(d)->solve(frictionless, Eigen::VectorXd(), sweeps(9)), to_string(d.kernel));
  }
}

TEST(PgsColored, RepeatedContactSetReusesTheLayoutWithNewValues) {
  // The same contacts again (a settled pile's next step): colours and batch layout are kept,
  // the batches refilled from the new J, b and λ⁰ — the result of a fresh solver on that problem.
  test::TestRng rng(12);
  const LcpProblem a = pile_problem(100, 150);
  {  // the same contacts again: a repeat is recognised
    ContactColorer colorer;
    const auto dyn = all_dynamic(a);
    (void)colorer.color(a.constraints, dyn);
    ASSERT_TRUE(colorer.color(a.constraints, dyn).repeated);
  }
  LcpProblem next = a;
  next.J *= 1.25;
  for (int i = 0; i < next.rows(); ++i) next.b[i] += rng.uniform(-0.5, 0.5);
  Eigen::VectorXd l0(next.rows());
  for (int i = 0; i < next.rows(); ++i) l0[i] = rng.uniform(0, 1);
  for (const int threads : {1, 2}) {
    PgsColoredDef d;
    d.threads = threads;
    d.min_batches_per_thread = 0;
    const auto solver = make_pgs_colored(d);
    (void)solver->solve(a, Eigen::VectorXd(), sweeps(5));
    test::expect_bit_equal(solver->solve(next, l0, sweeps(9)), make_pgs_colored(d)->solve(next, l0, sweeps(9)),
                     "repeat after a");
    test::expect_bit_equal(solver->solve(a, Eigen::VectorXd(), sweeps(9)),
                     make_pgs_colored(d)->solve(a, Eigen::VectorXd(), sweeps(9)), "a again");
  }
}

TEST(PgsColored, NonFiniteIterateStopsEveryKernelAtTheSameSweep) {
  // Two ways to overflow: a λ⁰ whose Δu⁰ = M⁻¹ Jᵀ λ⁰ Δt is not finite (reported in sweep 1, as a
  // check after the sweep would), and normal rows whose b_i/A_ii overflows (λ_n = ∞, and the
  // velocities the kernels store). Every kernel reports Diverged in the same sweep and returns
  // the same last finite iterate.
  test::TestRng rng(4);
  const LcpProblem p = test::random_contact(30, 40, true, rng, 0.5, 4);
  LcpProblem q = p;
  for (const ContactConstraint& k : q.constraints) q.b[k.normal_row] = -1e308;
  const Eigen::VectorXd huge = Eigen::VectorXd::Constant(p.rows(), 1e308);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(p.rows());
  const std::vector<std::pair<const LcpProblem*, Eigen::VectorXd>> cases = {{&p, huge}, {&q, zero}};
  for (const auto& [problem, l0] : cases) {
    const SolveResult first = make_pgs_colored()->solve(*problem, l0, sweeps(50));
    ASSERT_EQ(first.status, SolveStatus::Diverged) << first.message;
    ASSERT_TRUE(first.lambda.allFinite());
    for (const PgsColoredDef& d : test::pgs_colored_kernel_defs())
      test::expect_bit_equal(first, make_pgs_colored(d)->solve(*problem, l0, sweeps(50)), to_string(d.kernel));
  }
}

TEST(PgsColored, UnavailableKernelIsRefused) {
  EXPECT_TRUE(pgs_colored_kernel_available(PgsColoredKernel::Scalar));
  EXPECT_NE(pgs_colored_auto_kernel(), PgsColoredKernel::Auto);
  for (PgsColoredKernel k : {PgsColoredKernel::Avx2, PgsColoredKernel::Avx512}) {
    PgsColoredDef d;
    d.kernel = k;
    if (pgs_colored_kernel_available(k)) {
      EXPECT_NO_THROW((void)make_pgs_colored(d));
    } else {
      EXPECT_THROW((void)make_pgs_colored(d), InvalidArgument);
    }
  }
}

TEST(PgsColored, SameFixedPointAsPgsOnRandomProblems) {
  for (bool friction : {false, true}) {
    for (uint64_t seed = 1; seed <= 4; ++seed) {
      test::TestRng rng(seed);
      // Fewer rows than body dofs: A is non-singular, the solution unique.
      const LcpProblem p = test::random_contact(50, 40, friction, rng, 0.5, 3);
      const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(20000, 1e-12));
      const SolveResult c = make_solver("pgs-colored")->solve(p, Eigen::VectorXd(), sweeps(20000, 1e-12));
      ASSERT_EQ(a.status, SolveStatus::Converged) << a.message;
      ASSERT_EQ(c.status, SolveStatus::Converged) << c.message;
      EXPECT_LE(c.residual, 1e-9);
      EXPECT_LE(max_abs(a.lambda - c.lambda), 1e-8 * std::max(1.0, max_abs(a.lambda)))
          << "friction " << friction << " seed " << seed;
    }
  }
}

TEST(PgsColored, SameFixedPointAsPgsOnAPile) {
  const LcpProblem p = pile_problem(100, 150);
  // On a pile λ need not be unique (more rows than dofs); the body velocities and the
  // natural residual are what both must agree on.
  const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(30000, 1e-10));
  const SolveResult c = make_solver("pgs-colored")->solve(p, Eigen::VectorXd(), sweeps(30000, 1e-10));
  EXPECT_EQ(c.status, SolveStatus::Converged) << c.message;
  EXPECT_LE(a.residual, 1e-6);
  EXPECT_LE(c.residual, 1e-6);
  const Eigen::VectorXd ua = p.inv_mass.asDiagonal() * (p.J.transpose() * a.lambda) * p.dt;
  const Eigen::VectorXd uc = p.inv_mass.asDiagonal() * (p.J.transpose() * c.lambda) * p.dt;
  EXPECT_LE(max_abs(ua - uc), 1e-6);
  EXPECT_LE(max_abs(a.lambda - c.lambda), 1e-3 * std::max(1.0, max_abs(a.lambda)));
}

TEST(PgsColored, StaticBodiesDoNotConflictAndKeepTheFixedPoint) {
  test::TestRng rng(9);
  LcpProblem p = test::random_contact(40, 35, true, rng);
  // Up to 6 static bodies (M⁻¹ = 0; never written, so they may share a colour), chosen so
  // that every row keeps a dynamic body (A_ii > 0): not in a wall contact, no static pair.
  std::vector<std::uint8_t> dyn = all_dynamic(p);
  int statics = 0;
  for (int b = 0; b < 40 && statics < 6; ++b) {
    bool ok = true;
    for (const ContactConstraint& k : p.constraints) {
      const bool touches = k.body_a == b || k.body_b == b;
      const int other = k.body_a == b ? k.body_b : k.body_a;
      if (touches && (other < 0 || !dyn[static_cast<size_t>(other)])) ok = false;
    }
    if (!ok) continue;
    dyn[static_cast<size_t>(b)] = 0;
    for (int c = 0; c < 3; ++c) p.inv_mass[3 * b + c] = 0.0;
    ++statics;
  }
  ASSERT_GE(statics, 3);
  ContactColorer colorer(false);
  EXPECT_TRUE(is_valid_coloring(p.constraints, dyn, colorer.color(p.constraints, dyn)));
  const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(20000, 1e-12));
  const SolveResult c = make_solver("pgs-colored")->solve(p, Eigen::VectorXd(), sweeps(20000, 1e-12));
  ASSERT_EQ(c.status, SolveStatus::Converged) << c.message;
  EXPECT_EQ(c.message.find("ran pgs"), std::string::npos) << c.message;
  EXPECT_LE(max_abs(a.lambda - c.lambda), 1e-8 * std::max(1.0, max_abs(a.lambda)));
}

TEST(PgsColored, CheckpointsSeeRowOrderedIterates) {
  test::TestRng rng(5);
  const LcpProblem p = test::random_contact(30, 50, true, rng);
  SolverOptions o = sweeps(12);
  o.checkpoints = {3, 12};
  std::vector<Eigen::VectorXd> seen;
  o.on_checkpoint = [&](int, const Eigen::VectorXd& l) { seen.push_back(l); };
  const SolveResult r = make_solver("pgs-colored")->solve(p, Eigen::VectorXd(), o);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[1], r.lambda);
  EXPECT_EQ(seen[0], make_solver("pgs-colored")->solve(p, Eigen::VectorXd(), sweeps(3)).lambda);
}

TEST(PgsColored, ProblemsWithoutContactStructureRunPgs) {
  test::TestRng rng(2);
  LcpProblem p = test::random_contact(10, 12, true, rng);
  p.constraints.clear();
  const SolveResult c = make_solver("pgs-colored")->solve(p, Eigen::VectorXd(), sweeps(30));
  const SolveResult a = make_solver("pgs")->solve(p, Eigen::VectorXd(), sweeps(30));
  EXPECT_NE(c.message.find("ran pgs"), std::string::npos) << c.message;
  EXPECT_EQ(c.lambda, a.lambda);
  EXPECT_THROW((void)make_solver("pgs-colored:0"), ConfigError);
  EXPECT_EQ(make_solver("pgs-colored:2")->name(), "pgs-colored");
  EXPECT_EQ(make_solver("pgs-colored:1:scalar")->name(), "pgs-colored");
  EXPECT_THROW((void)make_solver("pgs-colored:1:sse"), ConfigError);
  EXPECT_THROW((void)make_solver("pgs-colored:1:"), ConfigError);
}

TEST(PgsColored, SimulationIsDeterministic) {
  WorldDef def = default_world_def();
  def.bodies.count = 60;
  auto run = [&] {
    World world(def);
    const auto s = make_solver("pgs-colored");
    SolverOptions o = sweeps(50);
    o.record_theta = false;
    for (int k = 0; k < 80; ++k) world.step(*s, o);
    return world.bodies().position;
  };
  EXPECT_EQ(run(), run());
}

}  // namespace
}  // namespace dc
