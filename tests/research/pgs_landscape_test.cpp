// The landscape probe of the train-through-PGS objective (pgs_landscape.hpp): along the
// steepest-descent line a small step does what the gradient predicts, the first horizon is its
// own reference, G* is the least-squares grid of the read-back (normal equations hold), and the
// options are validated.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cnn/small_data_set.hpp"
#include "dc/core/error.hpp"
#include "dc/research/pgs_landscape.hpp"

namespace dc {
namespace {

std::vector<PgsSample> samples_of(LabelKind kind) {
  DataSetParams params = test::small_data_set_params(16.0, 80, 7, 30, 30);
  params.image.channels = parse_feature_channels("mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t");
  const int sims[] = {0};
  return collect_pgs_samples(params, sims, 10, {}, 0, kind);
}

const PgsSample& largest(const std::vector<PgsSample>& s) {
  return *std::max_element(s.begin(), s.end(),
                           [](const PgsSample& a, const PgsSample& b) { return a.problem.rows() < b.problem.rows(); });
}

TEST(PgsLandscape, SmallStepsFollowTheGradientAndTheFirstHorizonIsItsOwnReference) {
  for (const LabelKind kind : {LabelKind::Residual, LabelKind::Gain}) {
    const std::vector<PgsSample> samples = samples_of(kind);
    ASSERT_FALSE(samples.empty());
    const PgsSample& s = largest(samples);
    ASSERT_GE(s.problem.rows(), 30);
    for (const PgsLoss loss : {PgsLoss::Residual, PgsLoss::Distance}) {
      PgsLandscapeDef def;
      def.loss = loss;
      def.unrolls = {3, 12};
      def.steps = {1e-6, 1e-1};
      const std::vector<PgsLandscapeLine> lines = probe_pgs_landscape(s, def);
      ASSERT_EQ(lines.size(), 2u);
      for (const PgsLandscapeLine& L : lines) {
        ASSERT_GT(L.grad_norm, 0.0) << to_string(loss);
        EXPECT_LT(L.slope, 0.0);
        ASSERT_EQ(L.along_own.size(), def.steps.size());
        ASSERT_EQ(L.along_field.size(), def.path.size());
        // J(ε d) / (slope ε) → 1 as ε → 0: the probe's line is the gradient's.
        EXPECT_NEAR(L.along_own[0] / (L.slope * def.steps[0]), 1.0, 0.01) << to_string(loss) << " K " << L.unroll;
        EXPECT_LT(L.along_own[0], 0.0);
      }
      EXPECT_DOUBLE_EQ(lines[0].cos_to_first, 1.0);
      for (std::size_t e = 0; e < def.steps.size(); ++e) EXPECT_EQ(lines[0].along_first[e], lines[0].along_own[e]);
      EXPECT_LE(std::abs(lines[1].cos_to_first), 1.0 + 1e-12);
    }
  }
}

/// G* solves the normal equations Rᵀ(R G − δ) = 0 (up to CGLS's tolerance) and fits δ better
/// than G = 0 does.
TEST(PgsLandscape, CorrectionGridIsTheReadBacksLeastSquaresFit) {
  for (const LabelKind kind : {LabelKind::Residual, LabelKind::Gain}) {
    const std::vector<PgsSample> samples = samples_of(kind);
    const PgsSample& s = largest(samples);
    const std::vector<float> G = least_squares_correction_grid(s, 400);
    const std::size_t n = 2 * static_cast<std::size_t>(s.features.h()) * s.features.w();
    ASSERT_EQ(G.size(), n);
    std::vector<double> delta, fit(2 * static_cast<std::size_t>(s.readback.points()));
    s.problem.constraints.gather(Eigen::VectorXd(s.lambda_star - s.lambda_prev), delta);
    s.readback.forward(G.data(), fit);
    double r2 = 0, d2 = 0;
    std::vector<double> r(fit.size());
    for (std::size_t i = 0; i < fit.size(); ++i) {
      r[i] = fit[i] - delta[i];
      r2 += r[i] * r[i];
      d2 += delta[i] * delta[i];
    }
    ASSERT_GT(d2, 0.0);
    EXPECT_LT(r2, d2);
    std::vector<float> g0(n, 0.0f), g1(n, 0.0f);
    s.readback.adjoint(delta, g0.data());
    s.readback.adjoint(r, g1.data());
    double n0 = 0, n1 = 0;
    for (std::size_t i = 0; i < n; ++i) {
      n0 += double(g0[i]) * g0[i];
      n1 += double(g1[i]) * g1[i];
    }
    EXPECT_LT(std::sqrt(n1), 1e-3 * std::sqrt(n0)) << to_string(kind);
  }
}

TEST(PgsLandscape, RejectsBadOptions) {
  PgsLandscapeDef def;
  def.unrolls = {};
  EXPECT_THROW(def.validate(), ConfigError);
  def.unrolls = {0};
  EXPECT_THROW(def.validate(), ConfigError);
  def.unrolls = {10};
  def.steps = {0.1, -1};
  EXPECT_THROW(def.validate(), ConfigError);
  def.steps = {0.1};
  def.cgls_iterations = 0;
  EXPECT_THROW(def.validate(), ConfigError);
  def.cgls_iterations = 5;
  EXPECT_NO_THROW(def.validate());
}

}  // namespace
}  // namespace dc
