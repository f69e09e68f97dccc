// The SPH round-trip study (sph_study.hpp) on a short run of the seed scene: one row per
// setting in the documented order, Shepard exact up to rounding and ranked first, the legacy
// sum-to-one weights losing force (docs/sph.md), the files written, and the options validated.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "dc/core/error.hpp"
#include "dc/research/sph_study.hpp"
#include "temp_dir.hpp"

namespace dc {
namespace {

SphStudyDef short_study() {
  SphStudyDef def;
  def.seeds = {1};
  def.steps = 120;
  def.sweeps = 50;
  def.kernels = {SphKernelType::Poly6, SphKernelType::Spiky};
  def.spacings = {0.5};
  def.ratios = {0.71, 1.0};
  return def;
}

const SphStudyResults& short_results() {
  static const SphStudyResults r = run_sph_study(WorldDef{}, short_study());
  return r;
}

TEST(SphStudy, MeasuresEverySettingInOrderOverTheSameContacts) {
  std::size_t seeds = 0, frames = 0, contacts = 0;
  const SphStudyResults r = run_sph_study(WorldDef{}, short_study(), [&](std::uint64_t seed, std::size_t f, std::size_t c) {
    EXPECT_EQ(seed, 1u);
    ++seeds;
    frames += f;
    contacts += c;
  });
  EXPECT_EQ(seeds, 1u);
  EXPECT_EQ(r.frames, frames);
  EXPECT_EQ(r.contacts, contacts);
  EXPECT_EQ(r.steps, 120);
  EXPECT_EQ(r.sweeps, 50);
  ASSERT_GT(r.frames, 0u);
  const SphStudyDef& def = r.def;
  ASSERT_EQ(r.rows.size(), def.normalisations.size() * def.kernels.size() * def.spacings.size() * def.ratios.size());
  std::size_t i = 0;
  for (const auto norm : def.normalisations)
    for (const auto kernel : def.kernels)
      for (const double d : def.spacings)
        for (const double ratio : def.ratios) {
          const SphStudyRow& row = r.rows[i++];
          EXPECT_EQ(row.s.normalisation, norm);
          EXPECT_EQ(row.s.kernel, kernel);
          EXPECT_EQ(row.s.d, d);
          EXPECT_EQ(row.s.ratio, ratio);
          // The threshold on |λ_n| selects contacts, not settings: every row sees the same ones.
          EXPECT_EQ(row.contacts, r.rows.front().contacts);
          EXPECT_LE(row.median, row.p90);
        }
  EXPECT_GT(r.rows.front().contacts, 0u);
  EXPECT_LE(r.rows.front().contacts, r.contacts);
}

TEST(SphStudy, ShepardIsExactAndRankedFirstWhileLegacyWeightsLoseForce) {
  const SphStudyResults& r = short_results();
  for (const SphStudyRow& row : r.rows) {
    if (row.s.normalisation == SphNormalisation::Shepard) {
      EXPECT_LT(row.median, kSphStudyExact) << to_string(row.s.kernel) << " h/d " << row.s.ratio;
      EXPECT_NEAR(row.retained_n, 1.0, 1e-12);
    }
    if (row.s.normalisation == SphNormalisation::SumToOneLegacy) {
      EXPECT_LT(row.retained_n, 1.0);
    }
  }
  const SphStudyRow& best = best_sph_study_row(r);
  EXPECT_EQ(best.s.normalisation, SphNormalisation::Shepard);
  for (const SphStudyRow& row : r.rows) EXPECT_FALSE(sph_study_ranks_before(row, best));
  const SphStudyRow* legacy = legacy_seed_row(r);
  ASSERT_NE(legacy, nullptr);
  EXPECT_EQ(legacy->s.kernel, SphKernelType::Poly6);
  EXPECT_EQ(legacy->s.d, 0.5);
  EXPECT_EQ(legacy->s.ratio, 1.0);
  EXPECT_EQ(legacy->s.normalisation, SphNormalisation::SumToOneLegacy);
}

TEST(SphStudy, WritesOneCsvLinePerSettingAndTheReport) {
  const SphStudyResults& r = short_results();
  const test::TempDir tmp;
  const auto dir = tmp.path() / "out";
  write_sph_study(r, dir, "the seed scene", "1");
  std::ifstream csv(dir / "sph_study.csv");
  std::string line;
  std::size_t lines = 0;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line.rfind("kernel,d,h_over_d,h,normalisation,contacts,", 0), 0u);
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, r.rows.size());
  std::ifstream md_file(dir / "sph_study.md");
  std::stringstream md;
  md << md_file.rdbuf();
  EXPECT_EQ(md.str(), sph_study_markdown(r, "the seed scene", "1"));
  EXPECT_NE(md.str().find("Scene: the seed scene, seeds 1, 120 steps"), std::string::npos);
  EXPECT_NE(md.str().find("## Best setting"), std::string::npos);
  EXPECT_NE(md.str().find("## Legacy sum-to-one loss"), std::string::npos);
}

TEST(SphStudy, PercentagesReadAsTheReportPrintsThem) {
  EXPECT_EQ(sph_study_percent(0.447), "44.7 %");
  EXPECT_EQ(sph_study_percent(0.0123), "1.23 %");
  EXPECT_EQ(sph_study_percent(2e-16), "2.0e-14 %");
  EXPECT_EQ(sph_study_percent(0.0), "0 %");
  EXPECT_EQ(sph_study_percent(std::nan("")), "n/a");
}

TEST(SphStudy, RejectsBadOptionsAndStudiesWithoutContacts) {
  const auto rejects = [](void (*edit)(SphStudyDef&), const std::string& option) {
    SphStudyDef def = short_study();
    edit(def);
    try {
      def.validate();
      ADD_FAILURE() << option << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(option), std::string::npos) << e.what();
    }
  };
  rejects([](SphStudyDef& d) { d.steps = -1; }, "--steps");
  rejects([](SphStudyDef& d) { d.every = 0; }, "--every");
  rejects([](SphStudyDef& d) { d.sweeps = -1; }, "--sweeps");
  rejects([](SphStudyDef& d) { d.min_lambda = -1; }, "--min-lambda");
  rejects([](SphStudyDef& d) { d.seeds.clear(); }, "--seeds");
  rejects([](SphStudyDef& d) { d.kernels.clear(); }, "--kernels");
  rejects([](SphStudyDef& d) { d.normalisations.clear(); }, "--normalisations");
  rejects([](SphStudyDef& d) { d.spacings = {0.5, 0.0}; }, "--spacings");
  rejects([](SphStudyDef& d) { d.ratios = {-1.0}; }, "--ratios");
  SphStudyDef none = short_study();
  none.steps = 20;
  none.min_lambda = 1e12;
  EXPECT_THROW((void)run_sph_study(WorldDef{}, none), ConfigError);
}

}  // namespace
}  // namespace dc
