// A run of train --loss pgs-* (pgs_training_run.hpp): prepare --init, replay, evaluate the
// start, train with the per-epoch files.
#include "dc/research/pgs_training_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <vector>

#include "dc/cnn/data_set.hpp"
#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/learning/model_file.hpp"

namespace dc {

namespace fs = std::filesystem;

void PgsTrainingRunDef::validate() const {
  train.validate();
  if (init.empty())
    throw ConfigError("--loss " + std::string(to_string(train.loss)) +
                      " needs --init MODEL (a residual model of this data set)");
  if (every < 1) throw ConfigError("--every must be >= 1");
  if (!(deadzone >= 0)) throw ConfigError("--deadzone must be >= 0");
}

namespace {

/// The --init model with the data set's dead zone, on the data set's grid `image` (the box
/// may differ: the fully convolutional network is rebuilt for the data's nx × ny and takes
/// every parameter over by name, as the cnn starter does on another box). ConfigError when
/// the kernel, d, h or channels differ, or the network cannot run on that grid.
///
/// `gain_start` (train --gain from a residual model): the result is a gain model with the same
/// trunk, the output node's weights and bias zeroed and identity output statistics without
/// compression, so G = 0 and the first guess is builtin's exactly (a gain model's output is a
/// gain, not a numerator).
Model regridded(Model& init, const FeatureImageDef& image, double deadzone, const std::string& init_path,
                bool gain_start) {
  ModelGrid g = init.grid();
  const SphTransferDef &a = g.image.sph, &b = image.sph;
  if (a.kernel != b.kernel || a.grid.spacing != b.grid.spacing || a.support != b.support ||
      g.image.channels != image.channels)
    throw ConfigError("--init " + init_path + ": its kernel, node spacing, support or feature channels differ from the data set's");
  g.image = image;
  g.labels.deadzone = deadzone;
  if (gain_start) {
    g.labels.kind = LabelKind::Gain;
    g.labels.scale = 0.0;
  }
  Model m(init.network().arch(), g, init.network().input_shape().c);
  const std::string head = init.network().arch().layers.back().name + "/";
  std::vector<ParamRef> src = init.network().parameters(), dst = m.network().parameters();
  for (std::size_t i = 0; i < src.size(); ++i) {
    if (src[i].value->shape() != dst[i].value->shape())
      throw ConfigError("--init " + init_path + ": parameter '" + src[i].name + "' depends on the grid size (" +
                        std::to_string(init.grid().nx()) + " x " + std::to_string(init.grid().ny()) + " vs the data's " +
                        std::to_string(m.grid().nx()) + " x " + std::to_string(m.grid().ny()) + ")");
    *dst[i].value = *src[i].value;
    if (gain_start && dst[i].name.rfind(head, 0) == 0) dst[i].value->fill(0.0f);
  }
  m.input_stats = init.input_stats;
  m.output_stats =
      gain_start ? ChannelStats::identity(static_cast<int>(init.output_stats.mean.size())) : init.output_stats;
  return m;
}

/// Step 1: the model training starts from, checked against the data set.
Model start_model(const PgsTrainingRunDef& def, const DataSetReader& reader) {
  Model init = load_model(def.init);
  if (init.network().input_shape().c != reader.feature_channels())
    throw ConfigError("--init " + def.init + ": its feature channels differ from " + def.data + "'s");
  Model model = regridded(init, reader.params().image, def.deadzone, def.init,
                          def.gain && init.grid().labels.kind == LabelKind::Residual);
  if (!def.gain && model.grid().labels.kind == LabelKind::Gain)
    throw ConfigError("--init " + def.init + " is a gain model: add --gain to continue training it");
  return model;
}

/// Step 3: the start's mean objective over the validation simulations' samples.
PgsInitReport evaluate_start(Model& model, const std::vector<PgsSample>& samples, const PgsTrainDef& def) {
  const std::vector<int> val = pgs_validation_simulations(samples, def);
  std::vector<std::size_t> val_idx;
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (std::find(val.begin(), val.end(), samples[i].simulation) != val.end()) val_idx.push_back(i);
  const auto [objective, better] = pgs_objective_mean(model, samples, val_idx, def);
  return {objective, better};
}

/// Step 4's files: OUT when an epoch scores best so far, OUT.loss.csv after every epoch.
class EpochFiles {
 public:
  EpochFiles(Model& model, std::string out) : model_(model), out_(std::move(out)) {
    csv_ << "epoch,train_objective,validation_objective,validation_improved,seconds\n";
  }
  /// Writes the epoch's files; true when OUT now holds it.
  bool record(const PgsEpochReport& r) {
    // Without validation samples the training objective is the only score there is.
    const double score = std::isnan(r.validation_objective) ? r.train_objective : r.validation_objective;
    const bool improved = score < best_;
    if (improved) {
      best_ = score;
      best_epoch_ = r.epoch;
      save_model(model_, out_);
    }
    seconds_ += r.seconds;
    csv_ << r.epoch + 1 << ',' << r.train_objective << ',' << r.validation_objective << ',' << r.validation_improved
         << ',' << r.seconds << '\n';
    write_file_atomically(out_ + ".loss.csv", csv_.str());
    return improved;
  }
  [[nodiscard]] double best() const { return best_; }
  [[nodiscard]] int best_epoch() const { return best_epoch_; }
  [[nodiscard]] double seconds() const { return seconds_; }

 private:
  Model& model_;
  std::string out_;
  std::ostringstream csv_;
  double best_ = INFINITY;
  int best_epoch_ = -1;
  double seconds_ = 0;
};

}  // namespace

PgsTrainingOutcome run_pgs_training(const PgsTrainingRunDef& def, const PgsTrainingHooks& hooks) {
  def.validate();
  if (fs::exists(def.out) && !def.force) throw ConfigError(def.out + " exists; use --force to replace it");
  if (!fs::exists(def.data)) throw IoError(def.data + ": no such file");
  const auto keep_going = [&hooks] { return !hooks.keep_going || hooks.keep_going(); };
  PgsTrainingOutcome outcome;

  const DataSetReader reader(def.data);
  Model model = start_model(def, reader);
  std::vector<int> sims;
  for (const DataSetSimulation& s : reader.simulations()) sims.push_back(s.index);
  if (hooks.on_replay_start) hooks.on_replay_start();
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<PgsSample> samples =
      collect_pgs_samples(reader.params(), sims, def.every, keep_going, def.first_step, model.grid().labels.kind);
  if (!keep_going()) {
    outcome.replay_interrupted = true;
    return outcome;
  }
  const double replay_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (hooks.on_replayed) hooks.on_replayed({sims.size(), samples.size(), replay_s});

  const PgsInitReport start = evaluate_start(model, samples, def.train);
  outcome.init_objective = start.objective;
  if (hooks.on_init) hooks.on_init(start);

  EpochFiles files(model, def.out);
  const auto on_epoch = [&](const PgsEpochReport& r) {
    const bool improved = files.record(r);
    if (hooks.on_epoch) hooks.on_epoch(r, improved);
    return keep_going();
  };
  const std::vector<PgsEpochReport> reports = train_through_pgs(model, samples, def.train, on_epoch, keep_going);
  if (files.best_epoch() < 0) throw ConfigError("training through PGS made no finished epoch (time limit too short?)");
  outcome.epochs = reports.size();
  outcome.best_epoch = files.best_epoch();
  outcome.best = files.best();
  outcome.seconds = files.seconds();
  return outcome;
}

}  // namespace dc
