// Training through the solver (docs/design.md §8.5): the unrolled PGS is the engine's "pgs"
// (same iterates for the same k), its reverse-mode gradient with respect to λ⁰ matches
// central differences for both losses, the contact read-back equals SphTransfer::gather and
// its adjoint is its transpose, the whole chain grid → λ⁰ → k sweeps → J is gradient-checked,
// and the replayed training problems are the data set's simulations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cnn/small_data_set.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/core/error.hpp"
#include "dc/core/rng.hpp"
#include "dc/lcp/lcp_solver.hpp"
#include "dc/engine/world.hpp"
#include "dc/research/pgs_samples.hpp"
#include "dc/research/pgs_trainer.hpp"
#include "dc/research/unrolled_pgs.hpp"
#include "dc/warmstart/oracle.hpp"

namespace dc {
namespace {

/// A pile of 14 circles in a 10 × 10 box after `steps` oracle steps: wall and pair contacts,
/// friction μ (0 = the frictionless kernels), some separating (speculative) contacts.
struct Step {
  LcpProblem problem;
  Eigen::VectorXd star, prev;
};
Step pile_step(double mu, int steps = 90) {
  WorldDef d;
  d.world.width = d.world.height = 10.0;
  d.bodies.count = 14;
  d.bodies.mean = {5.0, 5.0};
  d.bodies.sigma = 2.0;
  d.bodies.seed = 5;
  d.contact.friction = mu;
  World world(d);
  Eigen::VectorXd star;
  for (int s = 0; s < steps; ++s) {
    world.collide();
    star = solve_oracle(world.assemble()).lambda;
    world.integrate(star);
  }
  world.collide();
  Step out;
  out.problem = world.assemble();
  out.star = solve_oracle(out.problem).lambda;
  out.prev = Eigen::VectorXd::Zero(out.problem.rows());
  return out;
}

Eigen::VectorXd random_vector(int n, Rng& rng, double lo, double hi) {
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = lo + (hi - lo) * rng.uniform();
  return v;
}

TEST(UnrolledPgs, ForwardIsTheEnginesPgsForTheSameSweeps) {
  for (const double mu : {0.5, 0.0}) {
    const Step st = pile_step(mu);
    ASSERT_GT(st.problem.constraints.size(), 10);
    UnrolledPgs un(st.problem);
    const auto pgs = make_solver("pgs");
    Rng rng(3);
    for (const int k : {0, 1, 7, 40}) {
      Eigen::VectorXd l0 = random_vector(st.problem.rows(), rng, 0.0, 30.0);
      for (int i = 0; i < st.problem.rows(); ++i)
        if (st.problem.is_friction_row(i)) l0[i] = 0.0;  // feasible: |λ_t| ≤ μ λ_n
      SolverOptions o;
      o.max_sweeps = k;
      o.tolerance = 0.0;
      const Eigen::VectorXd engine = k == 0 ? l0 : pgs->solve(st.problem, l0, o).lambda;
      const Eigen::VectorXd& mine = un.forward(l0, k);
      for (int i = 0; i < st.problem.rows(); ++i) EXPECT_EQ(mine[i], engine[i]) << "mu " << mu << " k " << k << " row " << i;
    }
  }
}

/// Directional central differences of L(λ⁰) = loss after k sweeps against the reverse-mode
/// gradient. L is piecewise quadratic in λ⁰ (pieces fixed by the active sets), so a small
/// step that changes no active set gives the directional derivative to round-off.
void check_gradient(const Step& st, PgsLoss loss, int k) {
  UnrolledPgs un(st.problem);
  const int n = st.problem.rows();
  const auto L = [&](const Eigen::VectorXd& l0, Eigen::VectorXd* grad) {
    un.forward(l0, k);
    Eigen::VectorXd dl = Eigen::VectorXd::Zero(n), du = Eigen::VectorXd::Zero(un.velocity_entries());
    const double v = loss == PgsLoss::Residual ? un.residual_loss(dl, du) : un.distance_loss(st.star, dl);
    if (grad) *grad = un.backward(dl, loss == PgsLoss::Residual ? du : Eigen::VectorXd());
    return v;
  };
  Rng rng(11);
  int checked = 0;
  for (int trial = 0; trial < 6; ++trial) {
    // Interior start: the oracle's λ* perturbed (active sets away from their kinks).
    Eigen::VectorXd l0 = st.star + random_vector(n, rng, -2.0, 2.0);
    for (int i = 0; i < n; ++i)
      if (!st.problem.is_friction_row(i)) l0[i] = std::max(l0[i], 0.0);
    Eigen::VectorXd g;
    L(l0, &g);
    ASSERT_GT(g.norm(), 0.0);
    for (int dir = 0; dir < 4; ++dir) {
      const Eigen::VectorXd v = random_vector(n, rng, -1.0, 1.0);
      const double h = 1e-6;
      const double num = (L(l0 + h * v, nullptr) - L(l0 - h * v, nullptr)) / (2 * h);
      const double ana = g.dot(v);
      EXPECT_NEAR(ana, num, 1e-4 * (std::abs(ana) + std::abs(num)) + 1e-6)
          << to_string(loss) << " k " << k << " trial " << trial;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 24);
}

TEST(UnrolledPgs, ResidualLossGradientMatchesCentralDifferences) {
  check_gradient(pile_step(0.5), PgsLoss::Residual, 5);
  check_gradient(pile_step(0.5), PgsLoss::Residual, 25);
  check_gradient(pile_step(0.0), PgsLoss::Residual, 10);
}

TEST(UnrolledPgs, DistanceLossGradientMatchesCentralDifferences) {
  check_gradient(pile_step(0.5), PgsLoss::Distance, 5);
  check_gradient(pile_step(0.5), PgsLoss::Distance, 25);
}

TEST(UnrolledPgs, ResidualVanishesAtTheSolutionAndMatchesTheSweepStep) {
  const Step st = pile_step(0.5);
  UnrolledPgs un(st.problem);
  un.forward(st.star, 0);
  EXPECT_LT(un.residual().cwiseAbs().maxCoeff(), 1e-5);
  // Away from it, the residual is what PGS pays: it shrinks with the sweeps.
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(st.problem.rows());
  un.forward(zero, 1);
  const double r1 = un.residual().norm();
  un.forward(zero, 50);
  EXPECT_LT(un.residual().norm(), r1);
}

TEST(UnrolledPgs, RefusesProblemsWithoutJacobian) {
  const LcpProblem p = LcpProblem::standard(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Ones(2));
  EXPECT_THROW(UnrolledPgs{p}, InvalidArgument);
}

/// Replayed samples of a small data set: their features are the generator's, bit for bit.
TEST(PgsSamples, ReplayEqualsTheDataSetSimulation) {
  DataSetParams params = test::small_data_set_params(12.0, 40, 7, 8, 10);
  params.image.channels = parse_feature_channels("mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t");
  const SimulationRecord rec = *SimulationGenerator(params).run(1);
  const int sims[] = {1};
  const std::vector<PgsSample> s = collect_pgs_samples(params, sims, 3);
  ASSERT_EQ(s.size(), (rec.samples() + 2) / 3);
  const std::size_t F = s[0].features.size();
  for (std::size_t k = 0; k < s.size(); ++k) {
    EXPECT_EQ(s[k].step, rec.step[3 * k]);
    for (std::size_t i = 0; i < F; ++i) ASSERT_EQ(s[k].features[i], rec.features[3 * k * F + i]) << k << " " << i;
    // λ* per contact is the file's.
    std::vector<double> pairs;
    s[k].problem.constraints.gather(s[k].lambda_star, pairs);
    ASSERT_EQ(pairs.size(), static_cast<std::size_t>(2 * rec.contact_count[3 * k]));
  }
}

/// first_step: earlier steps are replayed but not kept; every counts from the first kept one.
TEST(PgsSamples, FirstStepSkipsTheEarlierSteps) {
  DataSetParams params = test::small_data_set_params(12.0, 40, 7, 8, 10);
  params.image.channels = parse_feature_channels("mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t");
  const SimulationRecord rec = *SimulationGenerator(params).run(1);
  ASSERT_GT(rec.samples(), 6u);
  const int first = rec.step[4];
  const int sims[] = {1};
  const std::vector<PgsSample> s = collect_pgs_samples(params, sims, 2, {}, first);
  ASSERT_EQ(s.size(), (rec.samples() - 4 + 1) / 2);
  const std::size_t F = s[0].features.size();
  for (std::size_t k = 0; k < s.size(); ++k) {
    EXPECT_EQ(s[k].step, rec.step[4 + 2 * k]);
    for (std::size_t i = 0; i < F; ++i) ASSERT_EQ(s[k].features[i], rec.features[(4 + 2 * k) * F + i]) << k << " " << i;
  }
  EXPECT_THROW((void)collect_pgs_samples(params, sims, 2, {}, -1), ConfigError);
}

/// ⟨R g, w⟩ = ⟨g, Rᵀ w⟩ for a random w, with v = R g already computed (and not ≈ 0).
void expect_adjoint_is_transpose(const ContactReadback& rb, const std::vector<float>& g, const std::vector<double>& v,
                                 Rng& rng) {
  std::vector<double> w(v.size());
  for (double& x : w) x = rng.uniform() - 0.5;
  std::vector<float> rtw(g.size(), 0.0f);
  rb.adjoint(w, rtw.data());
  double lhs = 0, rhs = 0;
  for (std::size_t i = 0; i < v.size(); ++i) lhs += v[i] * w[i];
  for (std::size_t i = 0; i < g.size(); ++i) rhs += double(g[i]) * double(rtw[i]);
  EXPECT_NEAR(lhs, rhs, 1e-5 * (std::abs(lhs) + 1));
  EXPECT_GT(std::abs(lhs), 1e-3);
}

TEST(ContactReadback, EqualsSphTransferGatherAndAdjointIsTranspose) {
  DataSetParams params = test::small_data_set_params(12.0, 40, 7, 8, 10);
  const SphTransferDef def = readback_transfer_def(params.image);
  SphTransfer transfer(def);
  Rng rng(2);
  std::vector<Vec2> pts;
  for (int k = 0; k < 9; ++k) pts.push_back({0.3 + 11.4 * rng.uniform(), 0.3 + 11.4 * rng.uniform()});
  SphGrid grid(def.grid);
  std::vector<float> g(grid.data().size());
  for (std::size_t i = 0; i < g.size(); ++i) grid.data()[i] = g[i] = static_cast<float>(rng.uniform() * 10 - 5);
  const std::span<const double> got = transfer.gather(grid, pts);
  const std::vector<double> ref(got.begin(), got.end());
  const ContactReadback rb(transfer, pts);
  std::vector<double> v(2 * pts.size());
  rb.forward(g.data(), v);
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(v[i], ref[i]) << i;
  expect_adjoint_is_transpose(rb, g, v, rng);
}

// The gain read-back v_k = λp_k · bilinear(D ⊙ G)(q_k) / bilinear(D)(q_k): a uniform gain field
// g0 comes back as λp·g0 at every point (the load-weighted average of a constant), a point
// without load nearby (D = 0 around it) gets 0, and the adjoint is the transpose.
TEST(ContactReadback, GainOfAUniformFieldIsLambdaPrevTimesItAndAdjointIsTranspose) {
  DataSetParams params = test::small_data_set_params(12.0, 40, 7, 8, 10);
  SphTransfer transfer(readback_transfer_def(params.image));
  Rng rng(5);
  std::vector<Vec2> pts;
  std::vector<double> lp;
  for (int k = 0; k < 9; ++k) {
    pts.push_back({0.3 + 5.0 * rng.uniform(), 0.3 + 11.4 * rng.uniform()});
    lp.push_back(1 + 20 * rng.uniform());
    lp.push_back(rng.uniform() * 4 - 2);
  }
  pts.push_back({11.5, 11.5});  // far from every loaded point, itself unloaded
  lp.push_back(0.0);
  lp.push_back(0.0);
  const ContactReadback rb = ContactReadback::gain(transfer, pts, lp);
  ASSERT_EQ(rb.points(), 10);
  const SphGrid probe(readback_transfer_def(params.image).grid);
  const std::size_t P = probe.data().size() / 2;
  std::vector<double> G(2 * P);
  for (std::size_t i = 0; i < P; ++i) G[i] = 0.25, G[P + i] = -0.5;
  std::vector<double> v(2 * pts.size());
  rb.forward(G.data(), v);
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
    EXPECT_NEAR(v[2 * k], 0.25 * lp[2 * k], 1e-12 * lp[2 * k]) << k;
    EXPECT_NEAR(v[2 * k + 1], -0.5 * lp[2 * k + 1], 1e-12) << k;
  }
  EXPECT_EQ(v[18], 0.0);
  EXPECT_EQ(v[19], 0.0);
  // A random field through the float path: the same as the double path to float rounding,
  // and ⟨R g, w⟩ = ⟨g, Rᵀ w⟩.
  std::vector<float> g(2 * P);
  for (std::size_t i = 0; i < g.size(); ++i) G[i] = g[i] = static_cast<float>(rng.uniform() * 2 - 1);
  std::vector<double> vd(v.size());
  rb.forward(g.data(), v);
  rb.forward(G.data(), vd);
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(v[i], vd[i]) << i;
  expect_adjoint_is_transpose(rb, g, v, rng);
  // One λ_prev pair per point.
  lp.pop_back();
  EXPECT_THROW((void)ContactReadback::gain(transfer, pts, lp), InvalidArgument);
}

/// The whole chain of one training sample: J(G) with G the correction grid (residual
/// read-back) or the gain field (gain read-back).
TEST(PgsObjective, ChainGradientMatchesCentralDifferences) {
  DataSetParams params = test::small_data_set_params(16.0, 80, 7, 30, 30);
  params.image.channels = parse_feature_channels("mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t");
  const int sims[] = {0};
  for (const LabelKind kind : {LabelKind::Residual, LabelKind::Gain}) {
    const std::vector<PgsSample> samples = collect_pgs_samples(params, sims, 10, {}, 0, kind);
    ASSERT_GE(samples.size(), 2u);
    const PgsSample& s = *std::max_element(samples.begin(), samples.end(), [](const PgsSample& a, const PgsSample& b) {
      return a.problem.rows() < b.problem.rows();
    });
    ASSERT_GE(s.problem.rows(), 30);
    for (const PgsLoss loss : {PgsLoss::Residual, PgsLoss::Distance}) {
      PgsObjective obj(s, loss, 3);
      const std::size_t n = 2 * static_cast<std::size_t>(s.features.h()) * s.features.w();
      Rng rng(4);
      std::vector<float> G(n), dG(n, 0.0f);
      for (float& x : G) x = static_cast<float>(rng.uniform() * 2 - 1);
      const double J0 = obj.evaluate(G.data(), dG.data());
      EXPECT_TRUE(std::isfinite(J0));
      // Zero correction is builtin itself: J = 0.
      std::vector<float> zero(n, 0.0f);
      EXPECT_NEAR(obj.evaluate(zero.data(), nullptr), 0.0, 1e-12);
      // The largest-gradient entries (those at contacts) against central differences.
      std::vector<std::size_t> order(n);
      for (std::size_t i = 0; i < n; ++i) order[i] = i;
      std::partial_sort(order.begin(), order.begin() + 8, order.end(),
                        [&](std::size_t a, std::size_t b) { return std::abs(dG[a]) > std::abs(dG[b]); });
      ASSERT_GT(std::abs(dG[order[0]]), 0.0f);
      for (int t = 0; t < 8; ++t) {
        const std::size_t i = order[static_cast<std::size_t>(t)];
        const float h = 1e-2f, g0 = G[i];
        G[i] = g0 + h;
        const double jp = obj.evaluate(G.data(), nullptr);
        G[i] = g0 - h;
        const double jm = obj.evaluate(G.data(), nullptr);
        G[i] = g0;
        const double num = (jp - jm) / (2.0 * double(h));
        EXPECT_NEAR(dG[i], num, 2e-2 * (std::abs(num) + std::abs(dG[i])) + 1e-7)
            << to_string(loss) << " " << to_string(kind) << " entry " << i;
      }
    }
  }
}

}  // namespace
}  // namespace dc
