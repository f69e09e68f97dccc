// deepcontact train --loss pgs-*: replay the data set's simulations to get each kept step's
// LCP (pgs_samples.hpp), start from the --init residual model, and train it through k
// unrolled PGS sweeps (pgs_trainer.hpp). Output: OUT (the best validation epoch, atomically),
// OUT.loss.csv (epoch,train_objective,validation_objective,validation_improved,seconds).
#include "commands/train_through_pgs.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cluster/sigint_guard.hpp"
#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/learning/model_file.hpp"
#include "dc/research/pgs_trainer.hpp"

namespace dc::cli {

namespace fs = std::filesystem;

void add_pgs_train_options(CLI::App* cmd, PgsTrainOptions& o) {
  cmd->add_option("--loss", o.loss,
                  "regression (MSE on the label grids, the default) or pgs-residual / pgs-distance: train a "
                  "residual --init model through --unroll PGS sweeps (docs/learning.md 'Training through PGS'); "
                  "pgs-field: regress its output on the read-back's least-squares field of lambda* - lambda_prev, "
                  "validated by pgs-distance after --unroll sweeps")
      ->capture_default_str();
  cmd->add_option("--unroll", o.unroll, "pgs-*: PGS sweeps unrolled per sample")->capture_default_str();
  cmd->add_option("--init", o.init, "pgs-*: the residual model to start from (arch, grid, statistics)");
  cmd->add_option("--time-limit", o.time_limit, "pgs-*: stop training after this many seconds (0 = none)")
      ->capture_default_str();
  cmd->add_option("--pgs-floor", o.floor, "pgs-*: f [N] of the objective log(L + rows f^2)")->capture_default_str();
  cmd->add_option("--clip", o.clip, "pgs-*: clip the minibatch gradient to this global norm (0 = off)")
      ->capture_default_str();
  cmd->add_option("--field-iterations", o.field_iterations,
                  "pgs-field: CGLS iterations of the target field (fewer = smoother; least_squares_field.hpp)")
      ->capture_default_str();
  cmd->add_flag("--gain", o.gain,
                "pgs-*: train a GAIN model, lambda0 = lambda_prev (1 + read-back of a gain field), from the residual "
                "--init (its trunk kept, its output layer zeroed: training starts at builtin; docs/learning.md)");
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


}  // namespace

void run_train_through_pgs(const PgsTrainOptions& o, const PgsTrainCommon& c) {
  PgsTrainDef def;
  def.loss = parse_pgs_loss(o.loss);
  def.unroll = o.unroll;
  def.epochs = c.epochs;
  def.batch = c.batch;
  def.learning_rate = c.lr;
  def.momentum = c.momentum;
  def.weight_decay = c.weight_decay;
  def.validation_fraction = c.val;
  def.seed = c.seed;
  def.time_limit = o.time_limit;
  def.floor = o.floor;
  def.clip = o.clip;
  def.field_iterations = o.field_iterations;
  def.validate();
  if (o.init.empty()) throw ConfigError("--loss " + o.loss + " needs --init MODEL (a residual model of this data set)");
  if (c.every < 1) throw ConfigError("--every must be >= 1");
  if (!(c.deadzone >= 0)) throw ConfigError("--deadzone must be >= 0");
  if (fs::exists(c.out) && !c.force) throw ConfigError(c.out + " exists; use --force to replace it");
  if (!fs::exists(c.data)) throw IoError(c.data + ": no such file");
  if (c.threads > 0) omp_set_num_threads(c.threads);

  const DataSetReader reader(c.data);
  Model init = load_model(o.init);
  if (init.network().input_shape().c != reader.feature_channels())
    throw ConfigError("--init " + o.init + ": its feature channels differ from " + c.data + "'s");
  Model model =
      regridded(init, reader.params().image, c.deadzone, o.init, o.gain && init.grid().labels.kind == LabelKind::Residual);
  if (!o.gain && model.grid().labels.kind == LabelKind::Gain)
    throw ConfigError("--init " + o.init + " is a gain model: add --gain to continue training it");

  std::vector<int> sims;
  for (const DataSetSimulation& s : reader.simulations()) sims.push_back(s.index);
  const SigintGuard sigint;
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<PgsSample> samples =
      collect_pgs_samples(reader.params(), sims, c.every, [] { return !interrupted(); }, c.first_step,
                          model.grid().labels.kind);
  if (interrupted()) {
    std::fprintf(stderr, "deepcontact: interrupted while replaying the simulations; nothing written\n");
    return;
  }
  const double replay_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("train: %s, unroll %d: replayed %zu simulations of %s -> %zu samples (every %d) in %.1f s; "
              "start %s, dead zone %g N, %d epochs, batch %d, lr %g, time limit %g s\n",
              to_string(def.loss), def.unroll, sims.size(), c.data.c_str(), samples.size(), c.every, replay_s,
              o.init.c_str(), c.deadzone, def.epochs, def.batch, def.learning_rate, def.time_limit);
  std::fflush(stdout);

  std::vector<std::size_t> val_idx;
  double init_objective = 0;
  {
    const std::vector<int> val = pgs_validation_simulations(samples, def);
    for (std::size_t i = 0; i < samples.size(); ++i)
      if (std::find(val.begin(), val.end(), samples[i].simulation) != val.end()) val_idx.push_back(i);
    const auto [j0, better0] = pgs_objective_mean(model, samples, val_idx, def);
    std::printf("train: the --init model: validation objective %.4f (%.0f %% of steps better than builtin after %d "
                "sweeps; 0 = builtin, log-units of the %s loss)\n", j0, 100 * better0, def.unroll,
                to_string(validation_loss(def.loss)));
    std::fflush(stdout);
    init_objective = j0;
  }
  std::ostringstream csv;
  csv << "epoch,train_objective,validation_objective,validation_improved,seconds\n";
  double best = INFINITY;
  int best_epoch = -1;
  double total_s = 0;
  const auto on_epoch = [&](const PgsEpochReport& r) {
    const double score = std::isnan(r.validation_objective) ? r.train_objective : r.validation_objective;
    const bool improved = score < best;
    if (improved) {
      best = score;
      best_epoch = r.epoch;
      save_model(model, c.out);
    }
    total_s += r.seconds;
    csv << r.epoch + 1 << ',' << r.train_objective << ',' << r.validation_objective << ',' << r.validation_improved
        << ',' << r.seconds << '\n';
    write_file_atomically(c.out + ".loss.csv", csv.str());
    std::printf("epoch %3d/%d  train %.4f  val %.4f (%.0f %% better than builtin)  |g| %.3g, %d clipped, %d skipped  %.1f s%s\n",
                r.epoch + 1, def.epochs, r.train_objective, r.validation_objective, 100 * r.validation_improved,
                r.grad_norm, r.clipped, r.skipped, r.seconds, improved ? "  *best" : "");
    std::fflush(stdout);
    return !interrupted();
  };
  const std::vector<PgsEpochReport> reports =
      train_through_pgs(model, samples, def, on_epoch, [] { return !interrupted(); });
  if (best_epoch < 0) throw ConfigError("training through PGS made no finished epoch (time limit too short?)");
  std::printf("train: best epoch %d of %zu (objective %.4f); %.1f s of training -> %s (%s.loss.csv)\n",
              best_epoch + 1, reports.size(), best, total_s, c.out.c_str(), c.out.c_str());
  // The file holds the best *trained* epoch; say so when that is worse than where it started.
  if (best > init_objective)
    std::fprintf(stderr,
                 "deepcontact: warning: no epoch beat the --init model's validation objective (%.4f; best epoch "
                 "%.4f): %s is worse than --init on the validation steps (try a smaller --lr)\n",
                 init_objective, best, c.out.c_str());
}

}  // namespace dc::cli
