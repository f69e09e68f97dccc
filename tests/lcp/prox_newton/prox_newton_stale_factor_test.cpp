// prox-newton's body space with a kept (stale) factor and the body-space finish: CG with an
// earlier H's factor solves the same subproblem as fresh factorisations, with no more of them;
// the coupled body-space finish reaches the hard target on its own (no dual finish, no pivoting,
// no safeguard) and agrees with newton-sparse's contact velocities.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/body_newton.hpp"
#include "solvers/prox_newton/frozen_subproblem.hpp"
#include "solvers/prox_newton/stale_pcg.hpp"

namespace dc {
namespace {

Eigen::VectorXd random_centre(const LcpProblem& p, test::TestRng& rng) {
  Eigen::VectorXd c(p.rows());
  for (int i = 0; i < p.rows(); ++i) c[i] = rng.uniform(-1, 3);
  project_feasible(p, c);
  return c;
}

// A second subproblem (another centre, the same δ) solved with the first one's factor kept as
// CG's preconditioner: the same solution as a fresh solver's, and no more factorisations.
TEST(ProxNewtonStaleFactor, SolvesTheSameSubproblemAsFreshFactors) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 1300);
    const LcpProblem p = test::random_contact(30, 50, true, rng, 0.4);
    const double delta = 1e-3 * p.A.diagonal().maxCoeff();
    for (const bool coupled : {false, true}) {
      solvers::prox::BodyNewton stale, fresh;
      stale.bind(p);
      fresh.bind(p);
      solvers::prox::FrozenSubproblem sub;
      solvers::prox::freeze(p, random_centre(p, rng), delta, sub);
      sub.coupled = coupled;
      sub.tolerance = 1e-11;
      sub.max_iterations = 100;
      Eigen::VectorXd warm = sub.centre;
      stale.solve(sub, warm);  // leaves its last factor kept
      solvers::prox::freeze(p, random_centre(p, rng), delta, sub);
      Eigen::VectorXd a = sub.centre, b = sub.centre;
      const auto rb = fresh.solve(sub, b);
      sub.stale_factor_iterations = 25;
      const auto ra = stale.solve(sub, a);
      EXPECT_TRUE(ra.converged) << seed << " " << coupled;
      EXPECT_TRUE(rb.converged) << seed << " " << coupled;
      EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 1e-8 * std::max(1.0, b.cwiseAbs().maxCoeff())) << seed << " " << coupled;
      EXPECT_LE(ra.factorizations, rb.factorizations) << seed << " " << coupled;
    }
  }
}

// CG with the exact factor as preconditioner converges at once; with an identity preconditioner
// it still solves an SPD system to the tolerance asked.
TEST(ProxNewtonStaleFactor, PcgSolvesSpdSystems) {
  test::TestRng rng(1400);
  const int n = 12;
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = rng.uniform(-1, 1);
  const Eigen::MatrixXd H = B * B.transpose() + Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = rng.uniform(-1, 1);
  const Eigen::LLT<Eigen::MatrixXd> llt(H);
  const solvers::LinearMap Hm = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { y = H * x; };
  const solvers::LinearMap exact = [&](const Eigen::VectorXd& r, Eigen::VectorXd& x) { x = llt.solve(r); };
  const solvers::LinearMap identity = [](const Eigen::VectorXd& r, Eigen::VectorXd& x) { x = r; };
  Eigen::VectorXd x;
  const auto a = solvers::prox::pcg(Hm, exact, b, x, 5, 1e-10);
  EXPECT_TRUE(a.converged);
  EXPECT_LE(a.iterations, 1);
  EXPECT_LE((H * x - b).norm(), 1e-9 * b.norm());
  const auto c = solvers::prox::pcg(Hm, identity, b, x, 4 * n, 1e-10);
  EXPECT_TRUE(c.converged);
  EXPECT_LE((H * x - b).norm(), 1e-8 * b.norm());
}

// The body-space finish (coupled passes, δ following the residual) with stale factors reaches
// the hard target without the dual finish, the pivoting finish or the safeguard.
TEST(ProxNewtonStaleFactor, BodyFinishReachesTheHardTargetAlone) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 1500);
    const LcpProblem p = test::random_contact(40, 60, true, rng, 0.3);
    SolverOptions o;
    o.max_sweeps = 300;
    const SolveResult ref = make_solver("newton-sparse")->solve(p, {}, o);
    ASSERT_EQ(ref.status, SolveStatus::Converged) << ref.message;
    ProxNewtonDef def;
    def.stale_factor_iterations = 20;
    def.body_finish = true;
    def.proximal_finish = false;
    def.pivot_rows = 0;
    def.safeguard_sweeps = 0;
    const SolveResult r = ProxNewtonSolver(def).solve(p, {}, o);
    EXPECT_EQ(r.status, SolveStatus::Converged) << seed << ": " << r.message;
    EXPECT_LE((lcp_velocity(p, r.lambda) - lcp_velocity(p, ref.lambda)).cwiseAbs().maxCoeff(), 1e-6) << seed;
  }
}

}  // namespace
}  // namespace dc
