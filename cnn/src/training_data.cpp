// Data set → training examples, the model grid, the reported MSE, the loss CSV
// (training_data.hpp).
#include "dc/cnn/training_data.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "dc/cnn/data_set_samples.hpp"
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
  const DataSetSamples source(r, def);
  std::vector<TrainingSample> out(source.size());
  const auto copy = [](const Tensor& batch, int k, Tensor& one) {
    one = Tensor(batch.shape().with_batch(1));
    std::memcpy(one.data(), batch.sample(k), sizeof(float) * batch.shape().sample_count());
  };
  Tensor x, y, w;
  std::vector<std::size_t> block;
  for (std::size_t first = 0; first < source.size(); first += 64) {
    block.clear();
    for (std::size_t i = first; i < std::min(source.size(), first + 64); ++i) block.push_back(i);
    source.read(block, x, y, w);
    for (std::size_t k = 0; k < block.size(); ++k) {
      TrainingSample& t = out[block[k]];
      copy(x, static_cast<int>(k), t.features);
      copy(y, static_cast<int>(k), t.labels);
      if (source.weight_channels() > 0) copy(w, static_cast<int>(k), t.weights);
      t.simulation = source.simulation(block[k]);
    }
  }
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
  return standardised_mse(model, InMemorySamples(data), sims, in);
}

double standardised_mse(Model& model, const SampleSource& data, const std::vector<int>& sims, bool in) {
  std::vector<std::size_t> picked;
  for (std::size_t i = 0; i < data.size(); ++i)
    if (std::binary_search(sims.begin(), sims.end(), data.simulation(i)) == in) picked.push_back(i);
  if (picked.empty()) return std::numeric_limits<double>::quiet_NaN();
  const MseLoss mse;
  double sum = 0;
  Tensor x, y, w;
  // Batches of 32: batch-1 inference pays a fork–join per layer per sample.
  for (std::size_t first = 0; first < picked.size(); first += 32) {
    const std::size_t b = std::min<std::size_t>(32, picked.size() - first);
    data.read(std::span<const std::size_t>(picked).subspan(first, b), x, y, w);
    Tensor pred = model.predict(x);
    compress_labels(pred, model.grid().labels.scale);  // back to the network's label space
    model.output_stats.apply(pred);
    model.output_stats.apply(y);
    sum += static_cast<double>(b) * mse(pred, y);
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
