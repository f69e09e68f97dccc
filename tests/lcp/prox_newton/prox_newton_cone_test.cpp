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
#include "solvers/prox_newton/cone/shift_trust.hpp"
#include "solvers/prox_newton/pivot_finish.hpp"

namespace dc {
namespace {

using solvers::prox::ConeNewton;
using solvers::prox::ConePoint;
using solvers::prox::ConeRegion;
using solvers::prox::ConeSubproblem;
using solvers::prox::ShiftTrust;
using solvers::prox::cone_jacobian;
using solvers::prox::project_cone;

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
    if (seed > 4) {  // a trust region that binds on some contacts (S_nt = 0 there)
      sub.shift_center = Eigen::VectorXd::Zero(p.rows());
      for (int i = 0; i < p.rows(); ++i) sub.shift_center[i] = rng.uniform(0, 1);
      sub.shift_radius = seed == 5 ? 0.3 : 0.05;
    }
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
        for (const int mode : {0, 1, 2}) {  // frozen shift, following, following in a trust region
          const bool follow = mode > 0;
          ProxNewtonDef def = cone_only();
          def.cone_follow_shift = follow;
          def.cone_trust_radius = mode == 2 ? 4 : 0;
          const SolveResult r = ProxNewtonSolver(def).solve(p, guess, test::capped_options());
          const std::string what = std::to_string(cs.friction) + "/" + std::to_string(cs.frictionless_every) +
                                   " seed " + std::to_string(seed) + " start " + std::to_string(start) +
                                   (follow ? " following" : "") + (mode == 2 ? " in a trust region" : "");
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

// A lead stage that reaches the target leaves nothing to the exact-cone passes: no pass, Newton
// iteration or factorisation after it (they would start again from the guess).
TEST(ProxNewtonCone, NoPassAfterALeadStageThatReachedTheTarget) {
  int by_lead = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    test::TestRng rng(seed + 2700);
    const LcpProblem p = test::random_contact(20, 30, true, rng, 0.5);
    ProxNewtonDef d = cone_only();
    d.lead_sweeps = 2000;
    ProxNewtonSolver s(d);
    SolverOptions o = test::capped_options(3000);
    o.tolerance = 1e-6 * std::max(1.0, p.b.lpNorm<Eigen::Infinity>());
    const SolveResult r = s.solve(p, {}, o);
    if (r.message.find("finished by nncg lead stage") == std::string::npos) continue;
    ++by_lead;
    const ProxNewtonStats st = s.last_stats();
    EXPECT_GT(st.lead_sweeps, 0) << r.message;
    EXPECT_EQ(st.outer, 0) << r.message;
    EXPECT_EQ(st.newton, 0) << r.message;
    EXPECT_EQ(st.factorizations, 0) << r.message;
  }
  EXPECT_GT(by_lead, 0) << "no seed was finished by the lead stage: the test checks nothing";
}

// With the trust region's radius 0 a following pass is the frozen-shift pass (the same λ), and
// where the region does not bind it is the unbounded following pass.
TEST(ProxNewtonCone, TrustRegionSpansFrozenAndFollowingShifts) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    test::TestRng rng(seed + 2600);
    const LcpProblem p = test::random_contact(20, 30, true, rng, 0.6);
    ConeNewton cone;
    ASSERT_TRUE(cone.bind(p));
    Eigen::VectorXd centre = Eigen::VectorXd::Zero(p.rows());
    for (int i = 0; i < p.rows(); ++i) centre[i] = rng.uniform(0, 2);
    Eigen::VectorXd shift;
    solvers::prox::de_saxce_shift(p, lcp_velocity(p, centre), shift);
    ConeSubproblem frozen;
    frozen.delta = 1e-2 * cone.max_diagonal();
    frozen.tolerance = 1e-12;
    frozen.max_iterations = 60;
    frozen.c = p.b + shift - frozen.delta * centre;
    ConeSubproblem bounded = frozen;
    bounded.follow_shift = true;
    bounded.c = p.b - frozen.delta * centre;
    bounded.shift_center = shift;
    bounded.shift_radius = 0.0;
    Eigen::VectorXd a = centre, b = centre;
    ASSERT_TRUE(cone.solve(frozen, a).converged) << seed;
    ASSERT_TRUE(cone.solve(bounded, b).converged) << seed;
    EXPECT_LE((a - b).cwiseAbs().maxCoeff(), 1e-8 * std::max(1.0, a.cwiseAbs().maxCoeff())) << seed;
    ConeSubproblem free = bounded, wide = bounded;
    free.shift_center.resize(0);
    wide.shift_radius = 1e9;
    Eigen::VectorXd c = centre, d = centre;
    const auto fo = cone.solve(free, c);
    const auto wo = cone.solve(wide, d);
    EXPECT_EQ(fo.converged, wo.converged) << seed;
    EXPECT_LE((c - d).cwiseAbs().maxCoeff(), 1e-8 * std::max(1.0, c.cwiseAbs().maxCoeff())) << seed;
  }
}

// The radius is τ times the shift's last move; an accepted pass that cut the residual
// `fast`-fold grows τ, a slower one keeps it, a rejected one shrinks it, and after `retries`
// rejections in a row the passes go back to frozen shifts with τ reset.
TEST(ProxNewtonCone, ShiftTrustGrowsShrinksAndGivesUp) {
  ShiftTrust t(4.0, 4.0, 2, 4.0);
  t.moved(0.5);
  ConeSubproblem sub;
  const Eigen::VectorXd shift = Eigen::VectorXd::Constant(3, 0.25);
  t.bound(shift, sub);
  EXPECT_EQ(sub.shift_center, shift);
  EXPECT_DOUBLE_EQ(sub.shift_radius, 2.0);
  EXPECT_TRUE(t.after_following(true, 0.5, 1.0));  // accepted, slow: τ kept
  EXPECT_DOUBLE_EQ(t.tau(), 4.0);
  EXPECT_TRUE(t.after_following(true, 0.2, 1.0));  // accepted, fast: τ grows
  EXPECT_DOUBLE_EQ(t.tau(), 16.0);
  EXPECT_TRUE(t.after_following(false, 2.0, 1.0));  // rejected: τ shrinks, still following
  EXPECT_DOUBLE_EQ(t.tau(), 4.0);
  EXPECT_TRUE(t.after_following(false, 2.0, 1.0));
  EXPECT_DOUBLE_EQ(t.tau(), 1.0);
  EXPECT_FALSE(t.after_following(false, 2.0, 1.0));  // third in a row: back to frozen
  EXPECT_DOUBLE_EQ(t.tau(), 4.0);
  EXPECT_TRUE(t.after_following(false, 2.0, 1.0));  // the count starts again
  ShiftTrust none(0.0, 4.0, 2, 4.0);  // no trust region: unbounded, one rejection gives up
  none.bound(shift, sub);
  EXPECT_EQ(sub.shift_center.size(), 0);
  EXPECT_TRUE(none.after_following(true, 0.5, 1.0));
  EXPECT_FALSE(none.after_following(false, 2.0, 1.0));
}

// exact_cone with the trust region and mass ratios 1e6 (every other body heavier): lemke's
// contact velocities from zero and random starts. The finishes stay on: δ is one scalar relative
// to max A_ii, so the heavy bodies' rows take proximal steps about 1e-6 of their distance and the
// passes alone stall there.
TEST(ProxNewtonCone, TrustRegionPassesMatchLemkeWithMassRatio) {
  int compared = 0;
  for (uint64_t seed = 801; seed <= 808; ++seed) {
    test::TestRng rng(seed);
    LcpProblem p = test::random_contact(20, 30, true, rng);
    for (int k = 0; k < p.inv_mass.size() / 3; k += 2) p.inv_mass.segment(3 * k, 3) *= 1e-6;
    p.A = p.J * SparseRowMatrix((p.inv_mass.asDiagonal() * SparseRowMatrix(p.J.transpose())) * p.dt);
    p.A.makeCompressed();
    // Lemke's pivoting ends on a ray on some of these problems: those have no reference.
    const auto po = solvers::prox::pivot_solve(p);
    if (!po.lambda) continue;
    const Eigen::VectorXd& ref = *po.lambda;
    ++compared;
    for (int start = 0; start < 2; ++start) {
      Eigen::VectorXd guess = Eigen::VectorXd::Zero(p.rows());
      if (start > 0)
        for (int i = 0; i < p.rows(); ++i) guess[i] = rng.uniform(-1, 3);
      ProxNewtonDef def;
      def.exact_cone = true;
      def.cone_trust_radius = 4;
      const SolveResult r = ProxNewtonSolver(def).solve(p, guess, test::capped_options(3000));
      EXPECT_EQ(r.status, SolveStatus::Converged) << seed << ": " << r.message;
      EXPECT_LE(r.residual, bound(p)) << seed;
      EXPECT_LE(velocity_gap(p, ref, r.lambda), 1e-6) << seed << " start " << start;
    }
  }
  EXPECT_GE(compared, 2);
}

// Following passes from the first, far from the solution, blow up: the trust region rejects
// them (hard residual above trust_accept times the best) and goes on from the best iterate, and
// the passes still lower the hard residual at least 1e4-fold.
TEST(ProxNewtonCone, RejectedFollowingPassesRestartFromTheBest) {
  int rejected = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    test::TestRng rng(seed + 2900);
    const LcpProblem p = test::random_contact(30, 60, true, rng, 0.8);
    Eigen::VectorXd guess(p.rows());
    for (int i = 0; i < p.rows(); ++i) guess[i] = rng.uniform(0, 50);
    ConeNewton cone;
    ASSERT_TRUE(cone.bind(p));
    solvers::prox::ConePassesDef d;
    d.shift = 1e-3;
    d.min_shift = 1e-6;
    d.shrink = 3;
    d.max_passes = 100;
    d.inner_iterations = 30;
    d.max_stalls = 20;
    d.iterations = 600;
    d.follow_shift = true;
    d.follow_after = 0;
    d.trust_radius = 4;
    project_feasible(p, guess);
    const double start = natural_residual(p, guess);
    const auto out = solvers::prox::run_cone_passes(p, cone, guess, bound(p), d);
    rejected += out.rejected;
    EXPECT_LE(out.best_residual, 1e-4 * start) << seed;
    EXPECT_EQ(natural_residual(p, out.best), out.best_residual) << seed;
  }
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace dc
