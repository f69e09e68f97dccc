// DataSetSamples: a data set's training examples read on demand (data_set_samples.hpp).
#include "dc/cnn/data_set_samples.hpp"

#include <algorithm>
#include <cstring>

#include "dc/core/error.hpp"
#include "dc/learning/labels.hpp"

namespace dc {

DataSetSamples::DataSetSamples(const DataSetReader& r, TrainingSampleDef def) : data_(r), def_(std::move(def)) {
  def_.validate();
  const std::vector<FeatureChannel>& channels = r.params().image.channels;
  const auto density_it = std::find(channels.begin(), channels.end(), FeatureChannel::ContactDensity);
  density_ = density_it == channels.end() ? -1 : static_cast<int>(density_it - channels.begin());
  if (def_.contact_weight > 0 && density_ < 0)
    throw ConfigError("--contact-weight needs a contact_density feature channel; " + r.path() + " has none");
  if (def_.labels.kind == LabelKind::Residual) {
    try {
      (void)lambda_prev_channels(channels, r.path());
    } catch (const ConfigError&) {
      throw ConfigError("--residual needs the feature channels lambda_prev_n and lambda_prev_t; " + r.path() +
                        " has none (generate it with --channels including them)");
    }
  }
  for (const DataSetSimulation& sim : r.simulations()) {
    std::int64_t k = 0;
    while (k < sim.samples && r.sample_step(sim.sample_begin + k) < def_.first_step) ++k;
    for (; k < sim.samples; k += def_.every) {
      rows_.push_back(sim.sample_begin + k);
      simulation_.push_back(sim.index);
    }
  }
  if (rows_.empty())
    throw ConfigError(r.path() + (def_.first_step > 0 ? ": no sample at or after --first-step " + std::to_string(def_.first_step)
                                                      : std::string(": the data set holds no samples")));
}

Shape DataSetSamples::feature_shape() const { return {1, data_.feature_channels(), data_.ny(), data_.nx()}; }

Shape DataSetSamples::label_shape() const { return {1, data_.label_channels(), data_.ny(), data_.nx()}; }

void DataSetSamples::read(std::span<const std::size_t> indices, Tensor& x, Tensor& y, Tensor& w) const {
  std::vector<std::int64_t> rows(indices.size());
  for (std::size_t j = 0; j < indices.size(); ++j) rows[j] = rows_.at(indices[j]);
  x = data_.features(rows);  // runs of consecutive rows: one read each
  y = data_.labels(rows);
  const std::vector<FeatureChannel>& channels = data_.params().image.channels;
  const Shape xs = feature_shape(), ys = label_shape();
  const std::size_t P = xs.plane();
  if (def_.contact_weight > 0) w.resize({static_cast<int>(rows.size()), 1, ys.h, ys.w});
  Tensor features(xs), labels(ys);  // training_labels works on one sample
  for (int j = 0; j < static_cast<int>(rows.size()); ++j) {
    std::memcpy(features.data(), x.sample(j), sizeof(float) * xs.sample_count());
    std::memcpy(labels.data(), y.sample(j), sizeof(float) * ys.sample_count());
    training_labels(labels, features, channels, def_.labels);
    std::memcpy(y.sample(j), labels.data(), sizeof(float) * ys.sample_count());
    if (def_.contact_weight <= 0) continue;
    const float* cd = x.sample(j) + static_cast<std::size_t>(density_) * P;
    float* wj = w.sample(j);
    for (std::size_t p = 0; p < P; ++p) wj[p] = 1.0f + (cd[p] > 0.0f ? static_cast<float>(def_.contact_weight) : 0.0f);
  }
}

}  // namespace dc
