// prox-newton against lemke, newton and newton-sparse, in body space (problems with J) and in
// the dual form (the same problems without J), from the solution, from random guesses, and on
// the problems that break Newton methods (rank deficiency, μ = 0, mixed μ, mass ratios 1e6);
// its exact line search against sampling, and the outer loop without finish or safeguard.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <string>
#include <vector>

#include "dc/lcp/fc2d_dat_file.hpp"
#include "dc/lcp/fc2d_problem.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/body_newton.hpp"
#include "solvers/prox_newton/dual_newton.hpp"
#include "solvers/prox_newton/exact_line_search.hpp"
#include "solvers/prox_newton/frozen_subproblem.hpp"

namespace dc {
namespace {

double bound(const LcpProblem& p) { return 1e-9 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()); }

SolveResult prox(const LcpProblem& p, const Eigen::VectorXd& lambda0 = {}, const ProxNewtonDef& def = {}) {
  return ProxNewtonSolver(def).solve(p, lambda0, test::capped_options());
}

/// Without the nncg safeguard and the pivoting finish: the outer loop and the newton-sparse
/// finishes alone.
ProxNewtonDef no_safeguard() {
  ProxNewtonDef d;
  d.safeguard_sweeps = 0;
  d.pivot_rows = 0;
  return d;
}

/// The problem with J and the same problem as read from a file (dual form).
std::vector<std::pair<std::string, LcpProblem>> both_forms(const LcpProblem& p) {
  return {{"body space", p}, {"dual form", test::without_jacobian(p)}};
}

double velocity_gap(const LcpProblem& p, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (lcp_velocity(p, a) - lcp_velocity(p, b)).cwiseAbs().maxCoeff();
}

/// The same contact problem with every other body 1e6 times heavier.
LcpProblem mass_ratio_problem(uint64_t seed) {
  test::TestRng rng(seed);
  LcpProblem p = test::random_contact(20, 30, true, rng);
  for (int k = 0; k < p.inv_mass.size() / 3; k += 2) p.inv_mass.segment(3 * k, 3) *= 1e-6;
  const SparseRowMatrix Minv_Jt_dt = (p.inv_mass.asDiagonal() * SparseRowMatrix(p.J.transpose())) * p.dt;
  p.A = p.J * Minv_Jt_dt;
  p.A.makeCompressed();
  return p;
}

TEST(ProxNewton, SameContactVelocitiesAsLemkeOnRankDeficientProblems) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed);
    const LcpProblem c = test::random_contact(10, 60, false, rng);  // 60 rows, rank ≤ 30
    const SolveResult a = make_solver("lemke")->solve(c, {}, test::capped_options(3000));
    ASSERT_EQ(a.status, SolveStatus::Converged) << a.message;
    for (const auto& [form, p] : both_forms(c)) {
      const SolveResult b = prox(p);
      ASSERT_EQ(b.status, SolveStatus::Converged) << form << ": " << b.message;
      EXPECT_LE(velocity_gap(c, a.lambda, b.lambda), 1e-6) << form << " seed " << seed;
    }
  }
}

TEST(ProxNewton, SameContactVelocitiesAsNewtonOnFrictionProblems) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed + 400);
    const LcpProblem c = test::random_contact(30, 25, true, rng);
    const SolveResult a = make_solver("newton")->solve(c, {}, test::capped_options(3000));
    ASSERT_EQ(a.status, SolveStatus::Converged) << a.message;
    auto forms = both_forms(c);
    forms.emplace_back("body space, coupled bounds", c);
    for (const auto& [form, p] : forms) {
      ProxNewtonDef def;
      def.coupled_bounds = form == "body space, coupled bounds";
      const SolveResult b = prox(p, {}, def);
      ASSERT_EQ(b.status, SolveStatus::Converged) << form << ": " << b.message;
      EXPECT_LE(velocity_gap(c, a.lambda, b.lambda), 1e-6) << form << " seed " << seed;
      for (int i = 0; i < p.rows(); ++i) {  // inside the friction box
        if (!p.is_friction_row(i)) continue;
        const double ln = b.lambda[p.normal_row[static_cast<size_t>(i)]];
        EXPECT_LE(std::abs(b.lambda[i]), p.mu[i] * ln + 1e-9 * std::max(1.0, ln));
      }
    }
  }
}

// The outer loop and the finish reach the hard target without the safeguard: the frozen bounds
// follow μ λ_n and the subproblems are solved exactly (kills mutations of the freeze and of the
// line search).
TEST(ProxNewton, SolvesTheHardProblemWithoutTheSafeguard) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 500);
    const LcpProblem c = test::random_contact(40, 60, true, rng, 0.3);
    const SolveResult ref = make_solver("newton-sparse")->solve(c, {}, test::capped_options());
    ASSERT_EQ(ref.status, SolveStatus::Converged) << ref.message;
    for (const auto& [form, p] : both_forms(c)) {
      const SolveResult b = prox(p, {}, no_safeguard());
      EXPECT_EQ(b.status, SolveStatus::Converged) << form << " seed " << seed << ": " << b.message;
      EXPECT_LE(b.residual, bound(p)) << form;
      EXPECT_LE(velocity_gap(c, ref.lambda, b.lambda), 1e-6) << form << " seed " << seed;
    }
  }
}

TEST(ProxNewton, CheckpointsFollowTheFinishesInOrderAndEndAtTheAnswer) {
  // Siconos' granular file: the passes stop above the target and the proximal finish solves
  // it; the caller's checkpoints must see the finish's iterates, not only the passes' best.
  const LcpProblem p = fc2d_to_lcp(
      read_fc2d_dat(std::string(DC_SOURCE_DIR) + "/tests/data/fc2d/fc2d_granularflowonwall_02020_00213.dat").problem);
  SolverOptions o = test::capped_options();
  for (int k = 1; k <= o.max_sweeps; ++k) o.checkpoints.push_back(k);
  std::vector<int> seen;
  std::vector<Eigen::VectorXd> iterates;
  o.on_checkpoint = [&](int k, const Eigen::VectorXd& lambda) {
    seen.push_back(k);
    if (iterates.empty() || iterates.back() != lambda) iterates.push_back(lambda);
  };
  ProxNewtonSolver s;
  const SolveResult r = s.solve(p, {}, o);
  ASSERT_EQ(r.status, SolveStatus::Converged) << r.message;
  const ProxNewtonStats st = s.last_stats();
  ASSERT_GT(st.finish_newton, 0) << r.message;
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_LT(seen[i - 1], seen[i]);
  EXPECT_EQ(iterates.back(), r.lambda);
  // The passes show at most one iterate each; the rest come from the finishes.
  EXPECT_GT(static_cast<int>(iterates.size()), st.outer + 1);
}

TEST(ProxNewton, FromTheSolutionConvergesInAtMostOneIteration) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 600);
    const LcpProblem c = test::random_contact(50, 100, true, rng);
    for (const auto& [form, p] : both_forms(c)) {
      const SolveResult star = prox(p);
      ASSERT_EQ(star.status, SolveStatus::Converged) << form << ": " << star.message;
      const SolveResult again = prox(p, star.lambda);
      EXPECT_EQ(again.status, SolveStatus::Converged) << form;
      EXPECT_LE(again.sweeps, 1) << form << ": " << again.message;
    }
  }
}

TEST(ProxNewton, ConvergesFromRandomGuesses) {
  test::TestRng rng(700);
  const LcpProblem c = test::random_contact(40, 90, true, rng);
  for (const auto& [form, p] : both_forms(c)) {
    for (int trial = 0; trial < 4; ++trial) {
      Eigen::VectorXd guess(p.rows());
      for (int i = 0; i < p.rows(); ++i) guess[i] = rng.uniform(-50, 50);
      const SolveResult r = prox(p, guess);
      EXPECT_EQ(r.status, SolveStatus::Converged) << form << " trial " << trial << ": " << r.message;
      EXPECT_LE(natural_residual(p, r.lambda), bound(p)) << form;
    }
  }
}

TEST(ProxNewton, HardProblemsConvergeAgreeingWithNewtonSparse) {
  test::TestRng rng(800);
  std::vector<std::pair<std::string, LcpProblem>> cases;
  cases.emplace_back("mu = 0", test::random_contact(10, 60, false, rng));
  cases.emplace_back("mixed mu", test::random_contact(20, 40, true, rng, 0.5, 3));  // every 3rd μ = 0
  cases.emplace_back("rank deficient with friction", test::random_contact(10, 80, true, rng));
  cases.emplace_back("mass ratio 1e6", mass_ratio_problem(801));
  cases.emplace_back("deep pile", test::deep_pile(6, 8, 0.5));
  for (auto& [what, c] : cases) {
    c.ensure_assembled_matrix();
    c.A.makeCompressed();
    const SolveResult ref = make_solver("newton-sparse")->solve(c, {}, test::capped_options());
    for (const auto& [form, p] : both_forms(c)) {
      const SolveResult r = prox(p);
      EXPECT_EQ(r.status, SolveStatus::Converged) << what << ", " << form << ": " << r.message;
      EXPECT_TRUE(r.lambda.allFinite());
      EXPECT_EQ(r.status == SolveStatus::Converged, natural_residual(p, r.lambda) <= bound(p)) << what;
      if (ref.status == SolveStatus::Converged && r.status == SolveStatus::Converged && !c.mu.any()) {
        EXPECT_LE(velocity_gap(c, ref.lambda, r.lambda), 1e-6) << what << ", " << form;
      }
    }
  }
}

TEST(ProxNewton, RerunsAreBitEqualAndTheMessageNamesThePart) {
  test::TestRng rng(900);
  const LcpProblem p = test::random_contact(30, 50, true, rng);
  ProxNewtonDef def;
  def.lead_sweeps = 0;  // the Newton passes factorise
  ProxNewtonSolver solver(def);
  const SolveResult a = solver.solve(p, {}, test::capped_options()), b = solver.solve(p, {}, test::capped_options());
  EXPECT_EQ(a.lambda, b.lambda);
  EXPECT_EQ(a.sweeps, b.sweeps);
  EXPECT_NE(a.message.find("finished by "), std::string::npos) << a.message;
  EXPECT_GE(solver.last_stats().factorizations, 1);
  EXPECT_EQ(make_solver("prox-newton")->name(), "prox-newton");
}

TEST(ProxNewton, ASolverObjectSolvesAnotherProblemAsAFreshOne) {
  // The body-space subproblem binds to each solve's problem at its first use (J, W, max A_ii):
  // after a solve of one pile, a solve of another is the fresh solver's bit for bit.
  test::TestRng rng(910);
  const LcpProblem first = test::random_contact(30, 50, true, rng), second = test::random_contact(25, 45, true, rng);
  ProxNewtonDef def;
  def.lead_sweeps = 0;  // the Newton passes factorise
  ProxNewtonSolver reused(def), fresh(def);
  (void)reused.solve(first, {}, test::capped_options());
  ASSERT_GE(reused.last_stats().factorizations, 1);
  const SolveResult a = reused.solve(second, {}, test::capped_options()), b = fresh.solve(second, {}, test::capped_options());
  EXPECT_EQ(a.lambda, b.lambda);
  EXPECT_EQ(a.sweeps, b.sweeps);
  EXPECT_EQ(reused.last_stats().factorizations, fresh.last_stats().factorizations);
}

TEST(ProxNewton, InvalidGuessIsInvalidInput) {
  test::TestRng rng(950);
  const LcpProblem p = test::random_contact(10, 15, true, rng);
  Eigen::VectorXd bad = Eigen::VectorXd::Zero(p.rows());
  bad[0] = NAN;
  const SolveResult r = prox(p, bad);
  EXPECT_EQ(r.status, SolveStatus::InvalidInput);
  EXPECT_TRUE(r.lambda.allFinite());
}

// The frozen box: friction rows at ∓μ max(0, λ_n^k) of the centre, fixed bounds elsewhere; and
// the subproblem's unique solution is the same in body space and in the dual form, inside it.
TEST(ProxNewtonSubproblem, BodySpaceAndDualFormSolveTheSameFrozenProblem) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 1000);
    const LcpProblem p = test::random_contact(30, 60, true, rng, 0.4);
    Eigen::VectorXd centre(p.rows());
    for (int i = 0; i < p.rows(); ++i) centre[i] = rng.uniform(-2, 5);
    project_feasible(p, centre);
    solvers::prox::FrozenSubproblem sub;
    const double delta = 1e-3 * p.A.diagonal().maxCoeff();
    solvers::prox::freeze(p, centre, delta, sub);
    for (int i = 0; i < p.rows(); ++i) {
      if (!p.is_friction_row(i)) {
        EXPECT_EQ(sub.lo[i], p.lo[i]);
        EXPECT_EQ(sub.hi[i], p.hi[i]);
        continue;
      }
      const double s = p.mu[i] * std::max(0.0, centre[p.normal_row[static_cast<size_t>(i)]]);
      EXPECT_EQ(sub.hi[i], s);
      EXPECT_EQ(sub.lo[i], -s);
    }
    sub.tolerance = 1e-12;
    sub.max_iterations = 50;
    Eigen::VectorXd a = centre, b = centre;
    solvers::prox::BodyNewton body;
    body.bind(p);
    solvers::prox::DualNewton dual;
    dual.bind(p.A);
    const auto ra = body.solve(sub, a), rb = dual.solve(sub, b);
    EXPECT_TRUE(ra.converged) << seed;
    EXPECT_TRUE(rb.converged) << seed;
    EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 1e-8) << seed;
    for (int i = 0; i < p.rows(); ++i) {
      EXPECT_GE(a[i], sub.lo[i]);
      EXPECT_LE(a[i], sub.hi[i]);
    }
  }
}

// Coupled bounds (the hard proximal subproblem): the body-space λ solves the shifted hard problem
// (A + δI)λ + b − δλ^k with the friction bounds μ max(0, λ_n) of that same λ, not the frozen
// box; it agrees with newton-sparse on that shifted problem.
TEST(ProxNewtonSubproblem, CoupledBodySpaceSolvesTheShiftedHardProblem) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 1100);
    LcpProblem p = test::random_contact(30, 40, true, rng, 0.4);
    p.ensure_assembled_matrix();
    Eigen::VectorXd centre(p.rows());
    for (int i = 0; i < p.rows(); ++i) centre[i] = rng.uniform(-2, 5);
    project_feasible(p, centre);
    const double delta = 1e-2 * p.A.diagonal().maxCoeff();
    solvers::prox::FrozenSubproblem sub;
    solvers::prox::freeze(p, centre, delta, sub);
    sub.coupled = true;
    sub.tolerance = 1e-11;
    sub.max_iterations = 100;
    Eigen::VectorXd a = centre;
    solvers::prox::BodyNewton body;
    body.bind(p);
    const auto ra = body.solve(sub, a);
    EXPECT_TRUE(ra.converged) << seed;
    LcpProblem shifted = test::without_jacobian(p);
    shifted.A = SparseRowMatrix(shifted.A + delta * SparseRowMatrix(Eigen::VectorXd::Ones(p.rows()).asDiagonal()));
    shifted.A.makeCompressed();
    shifted.b = p.b - delta * centre;
    EXPECT_LE(natural_residual(shifted, a), 1e-9) << seed;
    const SolveResult ref = make_solver("newton-sparse")->solve(shifted, centre, test::capped_options());
    ASSERT_EQ(ref.status, SolveStatus::Converged) << ref.message;
    EXPECT_LE((lcp_velocity(shifted, a) - lcp_velocity(shifted, ref.lambda)).cwiseAbs().maxCoeff(), 1e-7) << seed;
  }
}

// The factor kept across solves (same D and δ) never stands in for another: a BodyNewton that
// solved other subproblems first returns bit for bit what a fresh one returns.
TEST(ProxNewtonSubproblem, KeptFactorGivesTheSameIteratesAsAFreshOne) {
  test::TestRng rng(1200);
  const LcpProblem p = test::random_contact(25, 40, true, rng, 0.4);
  const double diag = p.A.diagonal().maxCoeff();
  solvers::prox::BodyNewton kept;
  kept.bind(p);
  for (const bool coupled : {false, true}) {
    for (const double shift : {1e-2, 1e-3, 1e-3}) {
      Eigen::VectorXd centre(p.rows());
      for (int i = 0; i < p.rows(); ++i) centre[i] = rng.uniform(-1, 3);
      project_feasible(p, centre);
      solvers::prox::FrozenSubproblem sub;
      solvers::prox::freeze(p, centre, shift * diag, sub);
      sub.coupled = coupled;
      sub.tolerance = 1e-10;
      sub.max_iterations = 60;
      solvers::prox::BodyNewton fresh;
      fresh.bind(p);
      Eigen::VectorXd a = centre, b = centre;
      const auto ra = kept.solve(sub, a), rb = fresh.solve(sub, b);
      EXPECT_EQ(a, b) << coupled << " " << shift;
      EXPECT_EQ(ra.iterations, rb.iterations);
      EXPECT_LE(ra.factorizations, rb.factorizations);
      EXPECT_LE(ra.factorizations, ra.iterations);
    }
  }
}

// The line search's t minimises f along the line: no sampled t does better, and f' vanishes.
TEST(ProxNewtonLineSearch, FindsTheMinimumOfThePiecewiseQuadraticCost) {
  test::TestRng rng(42);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 30;
    Eigen::VectorXd y(n), e(n), lo(n), hi(n);
    for (int i = 0; i < n; ++i) {
      y[i] = rng.uniform(-1, 1);
      e[i] = rng.uniform(-1, 1);
      const double s = rng.uniform(0, 2);
      lo[i] = i % 3 == 0 ? 0.0 : -s;  // normal-like rows [0, ∞), friction-like [−s, s]
      hi[i] = i % 3 == 0 ? INFINITY : s;
    }
    const double delta = rng.uniform(0.05, 1.0), q = rng.uniform(0.1, 2.0);
    solvers::prox::LineSearchInput in{&y, &e, &lo, &hi, delta, 0.0, q};
    double s0 = 0, c0 = 0;
    solvers::prox::line_slope(in, 0.0, s0, c0);
    in.a = -std::abs(rng.uniform(0.5, 3.0)) - std::max(0.0, s0);  // make d a descent direction
    // f(t) − f(0) from the row costs φ(y) = −λ* y − ½δλ*², λ* = clamp(−y/δ, lo, hi).
    const auto phi = [&](int i, double yy) {
      const double l = std::clamp(-yy / delta, lo[i], hi[i]);
      return -l * yy - 0.5 * delta * l * l;
    };
    const auto cost = [&](double t) {
      double f = in.a * t + 0.5 * in.q * t * t;
      for (int i = 0; i < n; ++i) f += phi(i, y[i] + t * e[i]) - phi(i, y[i]);
      return f;
    };
    const solvers::prox::LineSearchResult r = solvers::prox::exact_line_search(in);
    double s = 0, c = 0;
    solvers::prox::line_slope(in, r.t, s, c);
    EXPECT_GT(r.t, 0.0);
    EXPECT_LE(std::abs(s), 1e-9) << trial;
    const double best = cost(r.t);
    for (double t : {0.5 * r.t, 0.9 * r.t, 1.1 * r.t, 2.0 * r.t}) EXPECT_LE(best, cost(t) + 1e-9) << trial;
  }
}

}  // namespace
}  // namespace dc
