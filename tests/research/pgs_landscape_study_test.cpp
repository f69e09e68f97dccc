// The landscape study over a data set file (pgs_landscape_study.hpp): it keeps the samples
// train would keep, spread evenly down to max_samples, probes each exactly as the one-sample
// probe does (the parallel loop changes nothing), writes one CSV row per (sample, horizon)
// and reduces to medians; bad options and data are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "cnn/small_data_set.hpp"
#include "dc/bench/bench_statistics.hpp"
#include "dc/cnn/data_set_generation.hpp"
#include "dc/core/error.hpp"
#include "dc/research/pgs_landscape_study.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

DataSetParams residual_params() {
  DataSetParams params = test::small_data_set_params(16.0, 80, 7, 30, 30);
  params.image.channels = parse_feature_channels("mass,vx,vy,omega,contact_density,lambda_prev_n,lambda_prev_t");
  return params;
}

class PgsLandscapeStudyTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    DataSetGenerationDef d;
    d.params = residual_params();
    d.out = dir_->file("data.h5");
    d.simulations = 1;
    d.threads = 1;
    generate_data_set(d);
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static PgsLandscapeStudyDef def() {
    PgsLandscapeStudyDef d;
    d.data = dir_->file("data.h5");
    d.every = 10;
    d.first_step = 30;  // the pile has formed (the falling bodies of the first steps touch little)
    d.max_samples = 3;
    d.probe.unrolls = {3, 12};
    d.probe.steps = {1e-6, 1e-1};
    d.probe.path = {0.5, 1.0};
    d.probe.cgls_iterations = 20;
    return d;
  }
  static inline test::TempDir* dir_ = nullptr;
};

TEST_F(PgsLandscapeStudyTest, ProbesAnEvenSpreadOfTrainsSamplesAsTheOneSampleProbeDoes) {
  const PgsLandscapeStudyDef d = def();
  const PgsLandscapeStudy study = run_pgs_landscape_study(d);
  const int sims[] = {0};
  const std::vector<PgsSample> all = collect_pgs_samples(residual_params(), sims, d.every, {}, d.first_step);
  ASSERT_GT(all.size(), 3u);
  ASSERT_EQ(study.samples.size(), 3u);
  ASSERT_EQ(study.lines.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const PgsSample& s = all[i * all.size() / 3];
    EXPECT_EQ(study.samples[i].simulation, s.simulation);
    EXPECT_EQ(study.samples[i].step, s.step);
    EXPECT_EQ(study.samples[i].rows, s.problem.rows());
    const std::vector<PgsLandscapeLine> lines = probe_pgs_landscape(s, d.probe);
    ASSERT_EQ(study.lines[i].size(), lines.size());
    for (std::size_t k = 0; k < lines.size(); ++k) {
      EXPECT_EQ(study.lines[i][k].unroll, d.probe.unrolls[k]);
      EXPECT_EQ(study.lines[i][k].grad_norm, lines[k].grad_norm);
      EXPECT_EQ(study.lines[i][k].along_own, lines[k].along_own);
      EXPECT_EQ(study.lines[i][k].along_field, lines[k].along_field);
    }
  }
  const std::string csv = pgs_landscape_csv(study);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 3 * 2);
  EXPECT_EQ(csv.rfind("simulation,step,rows,unroll,grad_norm,slope,cos_to_first,cos_to_field,J_own_1e-06,", 0), 0u);
}

TEST_F(PgsLandscapeStudyTest, MediansAreOverTheSamplesPerHorizon) {
  const PgsLandscapeStudy study = run_pgs_landscape_study(def());
  const std::vector<PgsLandscapeHorizonMedians> m = pgs_landscape_medians(study);
  ASSERT_EQ(m.size(), 2u);
  for (std::size_t k = 0; k < m.size(); ++k) {
    EXPECT_EQ(m[k].unroll, study.def.probe.unrolls[k]);
    ASSERT_EQ(m[k].steps.size(), 2u);
    ASSERT_EQ(m[k].along_field.size(), 2u);
    std::vector<double> own, field;
    int down = 0;
    for (const auto& lines : study.lines) {
      own.push_back(lines[k].along_own[1]);
      field.push_back(lines[k].along_field[0]);
      down += lines[k].along_own[1] < 0;
    }
    EXPECT_EQ(m[k].steps[1].step, 1e-1);
    EXPECT_EQ(m[k].steps[1].along_own, bench::median_of(own));
    EXPECT_EQ(m[k].steps[1].descends_percent, 100.0 * down / 3.0);
    EXPECT_EQ(m[k].along_field[0], bench::median_of(field));
  }
  // The first horizon is its own reference direction (cosine 1 where there is a gradient).
  int with_gradient = 0;
  for (const auto& lines : study.lines)
    if (lines[0].grad_norm > 0) {
      ++with_gradient;
      EXPECT_DOUBLE_EQ(lines[0].cos_to_first, 1.0);
    }
  EXPECT_GT(with_gradient, 0);
  EXPECT_EQ(m[0].steps[0].along_first, m[0].steps[0].along_own);
}

TEST_F(PgsLandscapeStudyTest, RefusesBadOptionsAMissingFileAndAnEmptySelection) {
  PgsLandscapeStudyDef d = def();
  d.every = 0;
  EXPECT_THROW((void)run_pgs_landscape_study(d), ConfigError);
  d = def();
  d.max_samples = 0;
  EXPECT_THROW((void)run_pgs_landscape_study(d), ConfigError);
  d = def();
  d.probe.unrolls.clear();
  EXPECT_THROW((void)run_pgs_landscape_study(d), ConfigError);
  d = def();
  d.data = dir_->file("missing.h5");
  EXPECT_THROW((void)run_pgs_landscape_study(d), IoError);
  d = def();
  d.first_step = 100000;
  EXPECT_THROW((void)run_pgs_landscape_study(d), ConfigError);
}

}  // namespace
}  // namespace dc
