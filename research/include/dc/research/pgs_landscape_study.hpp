#pragma once
// The landscape study of `deepcontact pgs-landscape` (docs/research.md "Why long horizons do
// not train"; docs/learning.md "The objective's landscape"): the probe of pgs_landscape.hpp
// over a data set. It replays the data set's simulations as `train --loss pgs-*` does (the same
// samples for the same every/first_step), keeps at most max_samples of them evenly spread,
// probes each (in parallel, OpenMP) and reduces the lines to medians over the samples per
// horizon: whether J(ε d) follows the gradient's prediction slope·ε, whether the shortest
// horizon's descent direction still descends at K, and J along the straight path to the
// least-squares grid field G* of the exact correction.
#include <cstddef>
#include <string>
#include <vector>

#include "dc/research/pgs_landscape.hpp"

namespace dc {

struct PgsLandscapeStudyDef {
  std::string data;         ///< the data set (deepcontact generate) whose simulations are replayed
  bool gain = false;        ///< gain read-back (a gain model's output space) instead of the residual one
  int every = 8;            ///< keep every k-th step (≥ 1; as train --every)
  int first_step = 0;       ///< first step kept (≥ 0; as train --first-step)
  int max_samples = 32;     ///< at most this many samples (≥ 1), evenly spread over the kept ones
  PgsLandscapeDef probe;    ///< loss, horizons, steps, path, CGLS iterations, floor
  /// ConfigError naming the pgs-landscape option.
  void validate() const;
};

/// The probed sample: where it is in the data set and the size of its LCP.
struct PgsLandscapeSampleId {
  int simulation = 0;
  int step = 0;
  int rows = 0;
};

struct PgsLandscapeStudy {
  PgsLandscapeStudyDef def;
  std::vector<PgsLandscapeSampleId> samples;
  /// lines[i][k]: sample i at horizon def.probe.unrolls[k].
  std::vector<std::vector<PgsLandscapeLine>> lines;
};

/// Validates `def`, replays and probes. IoError when the data set does not exist, ConfigError
/// when no sample is kept.
PgsLandscapeStudy run_pgs_landscape_study(const PgsLandscapeStudyDef& def);

/// One CSV row per (sample, horizon): simulation, step, rows, unroll, grad_norm, slope,
/// cos_to_first, cos_to_field, then J_own_<ε>…, J_first_<ε>…, J_field_<t>….
std::string pgs_landscape_csv(const PgsLandscapeStudy& study);

/// Medians over the samples along one step length ε.
struct PgsLandscapeStepMedians {
  double step = 0;               ///< ε
  double along_own = 0;          ///< J(ε d_K)
  double actual_over_predicted = 0;  ///< J(ε d_K) / (slope_K·ε) (NaN for a sample with slope 0)
  double descends_percent = 0;   ///< share of the samples with J(ε d_K) < 0, in %
  double along_first = 0;        ///< J(ε d_1)
};

/// Medians over the samples at one horizon K.
struct PgsLandscapeHorizonMedians {
  int unroll = 0;
  double cos_to_first = 0;  ///< cos(g_K, g_1)
  double cos_to_field = 0;  ///< cos(−g_K, G*)
  std::vector<PgsLandscapeStepMedians> steps;
  std::vector<double> along_field;  ///< J(t G*), one per path entry
};

/// The medians (bench::median_of) per horizon, in the order of def.probe.unrolls.
std::vector<PgsLandscapeHorizonMedians> pgs_landscape_medians(const PgsLandscapeStudy& study);

}  // namespace dc
