// The landscape study over a data set (pgs_landscape_study.hpp): replay, probe, reduce.
#include "dc/research/pgs_landscape_study.hpp"

#include <filesystem>
#include <limits>
#include <sstream>
#include <utility>

#include "dc/bench/quantiles.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/core/error.hpp"
#include "dc/research/pgs_samples.hpp"

namespace dc {

void PgsLandscapeStudyDef::validate() const {
  probe.validate();
  if (every < 1) throw ConfigError("--every must be >= 1");
  if (first_step < 0) throw ConfigError("--first-step must be >= 0");
  if (max_samples < 1) throw ConfigError("--max-samples must be >= 1");
}

namespace {

/// The samples train --every/--first-step keep, then an even spread over them when there are
/// more than `max_samples`.
std::vector<PgsSample> kept_samples(const PgsLandscapeStudyDef& def) {
  if (!std::filesystem::exists(def.data)) throw IoError(def.data + ": no such file");
  const DataSetReader reader(def.data);
  std::vector<int> sims;
  for (const DataSetSimulation& s : reader.simulations()) sims.push_back(s.index);
  std::vector<PgsSample> samples = collect_pgs_samples(reader.params(), sims, def.every, {}, def.first_step,
                                                       def.gain ? LabelKind::Gain : LabelKind::Residual);
  if (static_cast<int>(samples.size()) > def.max_samples) {
    std::vector<PgsSample> kept;
    for (int i = 0; i < def.max_samples; ++i)
      kept.push_back(std::move(samples[static_cast<std::size_t>(i) * samples.size() / def.max_samples]));
    samples = std::move(kept);
  }
  if (samples.empty())
    throw ConfigError(def.data + ": no samples at --first-step " + std::to_string(def.first_step));
  return samples;
}

}  // namespace

PgsLandscapeStudy run_pgs_landscape_study(const PgsLandscapeStudyDef& def) {
  def.validate();
  const std::vector<PgsSample> samples = kept_samples(def);
  PgsLandscapeStudy study;
  study.def = def;
  study.lines.resize(samples.size());
#pragma omp parallel for schedule(dynamic)
  for (std::size_t i = 0; i < samples.size(); ++i) study.lines[i] = probe_pgs_landscape(samples[i], def.probe);
  for (const PgsSample& s : samples)
    study.samples.push_back({s.simulation, s.step, static_cast<int>(s.problem.rows())});
  return study;
}

std::string pgs_landscape_csv(const PgsLandscapeStudy& study) {
  const PgsLandscapeDef& def = study.def.probe;
  std::ostringstream csv;
  csv << "simulation,step,rows,unroll,grad_norm,slope,cos_to_first,cos_to_field";
  for (const double e : def.steps) csv << ",J_own_" << e;
  for (const double e : def.steps) csv << ",J_first_" << e;
  for (const double t : def.path) csv << ",J_field_" << t;
  csv << '\n';
  for (std::size_t i = 0; i < study.samples.size(); ++i)
    for (const PgsLandscapeLine& L : study.lines[i]) {
      const PgsLandscapeSampleId& s = study.samples[i];
      csv << s.simulation << ',' << s.step << ',' << s.rows << ',' << L.unroll << ',' << L.grad_norm << ','
          << L.slope << ',' << L.cos_to_first << ',' << L.cos_to_field;
      for (const double j : L.along_own) csv << ',' << j;
      for (const double j : L.along_first) csv << ',' << j;
      for (const double j : L.along_field) csv << ',' << j;
      csv << '\n';
    }
  return csv.str();
}

namespace {

PgsLandscapeStepMedians step_medians(const PgsLandscapeStudy& study, std::size_t k, std::size_t e) {
  const double eps = study.def.probe.steps[e];
  std::vector<double> ratio, own, first;
  int down = 0;
  for (const auto& ls : study.lines) {
    const PgsLandscapeLine& L = ls[k];
    ratio.push_back(L.slope != 0 ? L.along_own[e] / (L.slope * eps) : std::numeric_limits<double>::quiet_NaN());
    own.push_back(L.along_own[e]);
    first.push_back(L.along_first[e]);
    down += L.along_own[e] < 0;
  }
  PgsLandscapeStepMedians m;
  m.step = eps;
  m.along_own = bench::median_of(own);
  m.actual_over_predicted = bench::median_of(ratio);
  m.descends_percent = 100.0 * down / static_cast<double>(study.lines.size());
  m.along_first = bench::median_of(first);
  return m;
}

}  // namespace

std::vector<PgsLandscapeHorizonMedians> pgs_landscape_medians(const PgsLandscapeStudy& study) {
  const PgsLandscapeDef& def = study.def.probe;
  std::vector<PgsLandscapeHorizonMedians> out;
  for (std::size_t k = 0; k < def.unrolls.size(); ++k) {
    PgsLandscapeHorizonMedians h;
    h.unroll = def.unrolls[k];
    std::vector<double> cf, cg;
    for (const auto& ls : study.lines) {
      cf.push_back(ls[k].cos_to_first);
      cg.push_back(ls[k].cos_to_field);
    }
    h.cos_to_first = bench::median_of(cf);
    h.cos_to_field = bench::median_of(cg);
    for (std::size_t e = 0; e < def.steps.size(); ++e) h.steps.push_back(step_medians(study, k, e));
    for (std::size_t t = 0; t < def.path.size(); ++t) {
      std::vector<double> f;
      for (const auto& ls : study.lines) f.push_back(ls[k].along_field[t]);
      h.along_field.push_back(bench::median_of(f));
    }
    out.push_back(std::move(h));
  }
  return out;
}

}  // namespace dc
