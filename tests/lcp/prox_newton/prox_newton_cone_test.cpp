// prox-newton's exact-cone passes (ProxNewtonDef::exact_cone): the 2D cone projection against
// its defining properties, the body-space cost's gradient and Hessian against central
// differences, its Newton solve against the cone complementarity it solves, and the whole
// loop against lemke (contact velocities) from zero and random starts, with μ = 0 and mixed μ,
// without the finishes after it.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "dc/lcp/lcp_solver.hpp"
#include "dc/lcp/prox_newton.hpp"
#include "lcp/solver_test_problems.hpp"
#include "solvers/prox_newton/cone/cone_newton.hpp"
#include "solvers/prox_newton/cone/cone_passes.hpp"
#include "solvers/prox_newton/cone/friction_cone.hpp"
#include "solvers/prox_newton/pivot_finish.hpp"

namespace dc {
namespace {

using solvers::prox::ConeNewton;
using solvers::prox::ConePoint;
using solvers::prox::ConeRegion;
using solvers::prox::ConeSubproblem;
using solvers::prox::cone_jacobian;
using solvers::prox::project_cone;

SolverOptions options(int iterations = 300) {
  SolverOptions o;
  o.max_sweeps = iterations;
  return o;
}

/// The exact-cone passes alone: no proximal, pivoting or nncg finish after them.
ProxNewtonDef cone_only() {
  ProxNewtonDef d;
  d.exact_cone = true;
  d.proximal_finish = false;
  d.pivot_rows = 0;
  d.safeguard_sweeps = 0;
  d.cone_max_stalls = 20;
  return d;
}

double velocity_gap(const LcpProblem& p, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (lcp_velocity(p, a) - lcp_velocity(p, b)).cwiseAbs().maxCoeff();
}

/// Lemke's pivoting on the 2D Coulomb problem as a standard LCP (pivot_finish.hpp).
Eigen::VectorXd lemke(const LcpProblem& p) {
  const auto po = solvers::prox::pivot_solve(p);
  EXPECT_TRUE(po.lambda.has_value()) << po.why;
  return po.lambda.value_or(Eigen::VectorXd::Zero(p.rows()));
}

double bound(const LcpProblem& p) { return 1e-9 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>()); }

// Moreau: z = P(z) + (z − P(z)) with P(z) ∈ F, z − P(z) in the polar cone, the two orthogonal;
// ∂P matches central differences away from the region boundaries.
TEST(ProxNewtonCone, ProjectionIsMoreauDecompositionWithItsJacobian) {
  test::TestRng rng(2100);
  int regions[3] = {0, 0, 0};
  for (int k = 0; k < 3000; ++k) {
    const double mu = k % 7 == 0 ? 0.0 : rng.uniform(0.05, 2.0);
    const double zn = rng.uniform(-2, 2), zt = rng.uniform(-2, 2);
    const ConePoint p = project_cone(mu, zn, zt);
    ++regions[static_cast<int>(p.region)];
    const double qn = zn - p.n, qt = zt - p.t;
    EXPECT_GE(p.n, 0.0);
    EXPECT_LE(std::abs(p.t), mu * p.n + 1e-12);
    EXPECT_LE(qn + mu * std::abs(qt), 1e-12);  // polar cone
    EXPECT_NEAR(p.n * qn + p.t * qt, 0.0, 1e-12);
    const double h = 1e-7;
    const ConePoint a = project_cone(mu, zn + h, zt), b = project_cone(mu, zn - h, zt);
    const ConePoint c = project_cone(mu, zn, zt + h), d = project_cone(mu, zn, zt - h);
    if (a.region != p.region || b.region != p.region || c.region != p.region || d.region != p.region) continue;
    double nn = 0, nt = 0, tt = 0;
    cone_jacobian(p, nn, nt, tt);
    EXPECT_NEAR((a.n - b.n) / (2 * h), nn, 1e-6);
    EXPECT_NEAR((a.t - b.t) / (2 * h), nt, 1e-6);
    EXPECT_NEAR((c.n - d.n) / (2 * h), nt, 1e-6);
    EXPECT_NEAR((c.t - d.t) / (2 * h), tt, 1e-6);
  }
  for (const int r : regions) EXPECT_GT(r, 300);
}

// f's gradient against central differences of f, and H x against central differences of ∇f;
// with the shift following v, K x against central differences of F.
TEST(ProxNewtonCone, GradientAndHessianMatchDifferences) {
  int checked[2] = {0, 0};
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 2200);
    const LcpProblem p = test::random_contact(12, 20, true, rng, 0.4, 4);
    ConeNewton cone;
    ASSERT_TRUE(cone.bind(p));
    ConeSubproblem sub;
    sub.delta = 1e-2 * cone.max_diagonal();
    sub.c = p.b;
    for (int i = 0; i < p.rows(); ++i) sub.c[i] += rng.uniform(-0.5, 0.5);
    sub.follow_shift = seed > 3;
    const Eigen::Index m = p.J.cols();
    for (int trial = 0; trial < 5; ++trial) {
      Eigen::VectorXd v(m), x(m), g, gp, gm, hx;
      for (Eigen::Index j = 0; j < m; ++j) {
        v[j] = rng.uniform(-1, 1);
        x[j] = rng.uniform(-1, 1);
      }
      cone.cost(sub, v, &g);
      const double h = 1e-6;
      if (!sub.follow_shift) {  // F is no gradient when the shift follows v
        const double fd = (cone.cost(sub, v + h * x, nullptr) - cone.cost(sub, v - h * x, nullptr)) / (2 * h);
        EXPECT_NEAR(fd, g.dot(x), 1e-6 * std::max(1.0, std::abs(fd))) << seed;
      }
      const double k = 1e-8;  // small enough that no contact changes region (checked below)
      cone.cost(sub, v + k * x, &gp);
      cone.cost(sub, v - k * x, &gm);
      cone.hessian_times(sub, v, x, hx);
      Eigen::VectorXd hp, hm;
      cone.hessian_times(sub, v + k * x, x, hp);
      cone.hessian_times(sub, v - k * x, x, hm);
      if ((hp - hm).norm() > 0) continue;  // a region boundary inside the stencil
      const Eigen::VectorXd fdh = (gp - gm) / (2 * k);
      EXPECT_LE((fdh - hx).norm(), 1e-5 * std::max(1.0, hx.norm())) << seed;
      ++checked[sub.follow_shift ? 1 : 0];
    }
  }
  EXPECT_GE(checked[0], 5);
  EXPECT_GE(checked[1], 5);
}

// A converged subproblem solve satisfies the cone complementarity it stands for:
// λ = P_F(λ − (A λ + c + δ λ)) per contact.
TEST(ProxNewtonCone, SubproblemSolvesItsConeProblem) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 2300);
    const LcpProblem p = test::random_contact(30, 50, true, rng, 0.5, 3);
    ConeNewton cone;
    ASSERT_TRUE(cone.bind(p));
    ConeSubproblem sub;
    sub.delta = 1e-3 * cone.max_diagonal();
    sub.c = p.b;
    sub.tolerance = 1e-11;
    sub.max_iterations = 100;
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(p.rows());
    const auto out = cone.solve(sub, lambda);
    EXPECT_TRUE(out.converged) << seed;
    const Eigen::VectorXd w = p.A * lambda + sub.c + sub.delta * lambda;
    for (const ContactConstraint& k : p.constraints) {
      if (!k.has_friction()) {
        EXPECT_NEAR(lambda[k.normal_row], std::max(0.0, lambda[k.normal_row] - w[k.normal_row]), 1e-9);
        continue;
      }
      const int n = k.normal_row, t = k.tangent_row;
      const ConePoint q = project_cone(k.mu, lambda[n] - w[n], lambda[t] - w[t]);
      EXPECT_NEAR(lambda[n], q.n, 1e-9) << seed;
      EXPECT_NEAR(lambda[t], q.t, 1e-9) << seed;
    }
  }
}

// The passes alone reach the hard target with lemke's contact velocities: friction, μ = 0 and
// mixed μ, from zero and from random starts, with the shift frozen per pass and following the
// Newton iterate.
TEST(ProxNewtonCone, SameContactVelocitiesAsLemkeFromRandomStarts) {
  struct Case {
    bool friction;
    int frictionless_every;
  };
  for (const Case cs : {Case{true, 0}, Case{false, 0}, Case{true, 3}}) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
      test::TestRng rng(seed + 2400);
      const LcpProblem p = test::random_contact(20, 25, cs.friction, rng, 0.5, cs.frictionless_every);
      const Eigen::VectorXd ref = lemke(p);
      for (int start = 0; start < 3; ++start) {
        Eigen::VectorXd guess = Eigen::VectorXd::Zero(p.rows());
        if (start > 0)
          for (int i = 0; i < p.rows(); ++i) guess[i] = rng.uniform(-1, 3);
        for (const bool follow : {false, true}) {
          ProxNewtonDef def = cone_only();
          def.cone_follow_shift = follow;
          const SolveResult r = ProxNewtonSolver(def).solve(p, guess, options());
          const std::string what = std::to_string(cs.friction) + "/" + std::to_string(cs.frictionless_every) +
                                   " seed " + std::to_string(seed) + " start " + std::to_string(start) +
                                   (follow ? " following" : "");
          EXPECT_EQ(r.status, SolveStatus::Converged) << what << ": " << r.message;
          EXPECT_LE(r.residual, bound(p)) << what;
          EXPECT_LE(velocity_gap(p, ref, r.lambda), 1e-6) << what;
        }
      }
    }
  }
}

// A fixed point of the passes is a hard Coulomb solution: lemke's λ is one (its residual stays
// at the target after a pass from it), and the de Saxcé shift is μ|w_t| on normal rows only.
TEST(ProxNewtonCone, LemkeSolutionIsAFixedPoint) {
  test::TestRng rng(2500);
  const LcpProblem p = test::random_contact(20, 25, true, rng, 0.5);
  const Eigen::VectorXd ref = lemke(p);
  Eigen::VectorXd shift;
  const Eigen::VectorXd w = lcp_velocity(p, ref);
  solvers::prox::de_saxce_shift(p, w, shift);
  for (int i = 0; i < p.rows(); ++i) {
    if (p.is_friction_row(i)) {
      EXPECT_EQ(shift[i], 0.0);
      EXPECT_EQ(shift[p.normal_row[static_cast<size_t>(i)]], p.mu[i] * std::abs(w[i]));
    }
  }
  ConeNewton cone;
  ASSERT_TRUE(cone.bind(p));
  solvers::prox::ConePassesDef d;
  d.iterations = 50;
  d.max_passes = 1;
  const auto out = solvers::prox::run_cone_passes(p, cone, ref, 0.0, d);
  EXPECT_LE(natural_residual(p, ref), bound(p));
  EXPECT_LE(out.best_residual, bound(p));
}

}  // namespace
}  // namespace dc
