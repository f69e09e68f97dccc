// Data set → training examples, the model grid, the reported MSE, the loss CSV
// (training_data.hpp).
#include "dc/cnn/training_data.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "dc/core/error.hpp"
#include "dc/learning/mse_loss.hpp"

namespace dc {

void TrainingSampleDef::validate() const {
  if (every < 1) throw ConfigError("--every must be >= 1");
  if (first_step < 0) throw ConfigError("--first-step must be >= 0");
  if (!(contact_weight >= 0) || !std::isfinite(contact_weight))
    throw ConfigError("--contact-weight must be a finite number >= 0");
  if (!(labels.deadzone >= 0) || !std::isfinite(labels.deadzone))
    throw ConfigError("--deadzone must be a finite number >= 0");
  if (labels.deadzone > 0 && labels.kind != LabelKind::Residual)
    throw ConfigError("--deadzone applies to residual models only (add --residual)");
  if (!(labels.scale >= 0) || !std::isfinite(labels.scale))
    throw ConfigError("--label-scale must be a finite number >= 0");
}

std::vector<TrainingSample> load_training_samples(const DataSetReader& r, const TrainingSampleDef& def) {
  def.validate();
  const std::vector<FeatureChannel>& channels = r.params().image.channels;
  const auto density_it = std::find(channels.begin(), channels.end(), FeatureChannel::ContactDensity);
  const int density = density_it == channels.end() ? -1 : static_cast<int>(density_it - channels.begin());
  if (def.contact_weight > 0 && density < 0)
    throw ConfigError("--contact-weight needs a contact_density feature channel; " + r.path() + " has none");
  if (def.labels.kind == LabelKind::Residual) {
    try {
      (void)lambda_prev_channels(channels, r.path());
    } catch (const ConfigError&) {
      throw ConfigError("--residual needs the feature channels lambda_prev_n and lambda_prev_t; " + r.path() +
                        " has none (generate it with --channels including them)");
    }
  }
  std::vector<TrainingSample> out;
  for (const DataSetSimulation& sim : r.simulations()) {
    std::vector<std::int64_t> rows;
    std::int64_t k = 0;
    while (k < sim.samples && r.sample_step(sim.sample_begin + k) < def.first_step) ++k;
    for (; k < sim.samples; k += def.every) rows.push_back(sim.sample_begin + k);
    if (rows.empty()) continue;
    for (TrainingSample& t : r.training_samples(rows, sim.index)) {
      training_labels(t.labels, t.features, channels, def.labels);
      if (def.contact_weight > 0) {
        const std::size_t P = t.features.shape().plane();
        t.weights = Tensor(1, 1, t.features.h(), t.features.w());
        const float* cd = t.features.data() + static_cast<std::size_t>(density) * P;
        for (std::size_t p = 0; p < P; ++p)
          t.weights[p] = 1.0f + (cd[p] > 0.0f ? static_cast<float>(def.contact_weight) : 0.0f);
      }
      out.push_back(std::move(t));
    }
  }
  if (out.empty())
    throw ConfigError(r.path() + (def.first_step > 0 ? ": no sample at or after --first-step " + std::to_string(def.first_step)
                                                     : std::string(": the data set holds no samples")));
  return out;
}

ModelGrid model_grid_for(const DataSetReader& data, const LabelDef& labels) {
  ModelGrid g;
  g.image = data.params().image;
  g.label_channels = data.label_channel_names();
  g.labels = labels;
  return g;
}

double standardised_mse(Model& model, std::span<const TrainingSample> data, const std::vector<int>& sims, bool in) {
  std::vector<const TrainingSample*> picked;
  for (const TrainingSample& s : data)
    if (std::binary_search(sims.begin(), sims.end(), s.simulation) == in) picked.push_back(&s);
  if (picked.empty()) return std::numeric_limits<double>::quiet_NaN();
  const MseLoss mse;
  double sum = 0;
  Tensor x, y;
  // Batches of 32: batch-1 inference pays a fork–join per layer per sample.
  for (std::size_t first = 0; first < picked.size(); first += 32) {
    const int b = static_cast<int>(std::min<std::size_t>(32, picked.size() - first));
    x.resize(picked[first]->features.shape().with_batch(b));
    y.resize(picked[first]->labels.shape().with_batch(b));
    for (int k = 0; k < b; ++k) {
      const TrainingSample& s = *picked[first + static_cast<std::size_t>(k)];
      std::memcpy(x.sample(k), s.features.data(), s.features.size() * sizeof(float));
      std::memcpy(y.sample(k), s.labels.data(), s.labels.size() * sizeof(float));
    }
    Tensor pred = model.predict(x);
    compress_labels(pred, model.grid().labels.scale);  // back to the network's label space
    model.output_stats.apply(pred);
    model.output_stats.apply(y);
    sum += b * mse(pred, y);
  }
  return sum / static_cast<double>(picked.size());
}

double epoch_score(const EpochReport& e) { return std::isnan(e.validation_loss) ? e.train_loss : e.validation_loss; }

std::string loss_csv(const std::vector<EpochReport>& history) {
  std::ostringstream s;
  s << "epoch,train_loss,validation_loss,learning_rate,seconds\n";
  char buf[256];
  for (const EpochReport& e : history) {
    std::snprintf(buf, sizeof buf, "%d,%.9g,%.9g,%.9g,%.4f\n", e.epoch + 1, e.train_loss, e.validation_loss,
                  e.learning_rate, e.seconds);
    s << buf;
  }
  return s.str();
}

}  // namespace dc
