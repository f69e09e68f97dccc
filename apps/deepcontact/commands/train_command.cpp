// deepcontact train: fit the CNN to a data set written by `deepcontact generate` (docs/design.md
// §5; docs/learning.md "Training"): every K-th sample of each simulation, split by simulation
// into train / validation, Trainer → OUT (best validation loss), OUT.ckpt (latest state),
// OUT.loss.csv, OUT.loss.png. Samples stay on disk; at most --shuffle-buffer are held.
// After every epoch OUT and OUT.ckpt are written atomically, so a kill leaves the last
// finished epoch; `--resume` checks OUT.ckpt belongs to the same data and options and
// continues (bit-identical with the same --threads). SIGINT sets a flag the trainer polls
// between minibatches; the unfinished epoch is dropped and the command exits 130. The domain
// lives in the libraries (trainer.hpp, labels.hpp, training_data.hpp, train_checkpoint.hpp);
// this file parses options and runs a regression run; --loss pgs-* goes to train_through_pgs.cpp.
#include <CLI/CLI.hpp>
#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cluster/comm.hpp"
#include "cluster/mpi_train.hpp"
#include "cluster/sigint_guard.hpp"
#include "commands/cli_common.hpp"
#include "commands/commands.hpp"
#include "commands/train_through_pgs.hpp"
#include "dc/bench/progress_bar.hpp"
#include "dc/cnn/data_set.hpp"
#include "dc/cnn/data_set_samples.hpp"
#include "dc/cnn/train_checkpoint.hpp"
#include "dc/cnn/training_data.hpp"
#include "dc/core/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/output_lock.hpp"
#include "dc/io/output_path.hpp"
#include "dc/io/h5.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/model_file.hpp"
#include "dc/learning/trainer.hpp"
#include "dc/core/install_paths.hpp"

namespace dc::cli {
namespace {

namespace fs = std::filesystem;


struct TrainArgs {
  std::string data;
  std::string out;
  std::string arch;  // "" / "default" = default_arch(); "seed-dense"; or a TOML file
  int epochs = 30;
  int batch = TrainDef{}.batch_size;
  double lr = TrainDef{}.learning_rate;
  double momentum = TrainDef{}.momentum;
  double weight_decay = TrainDef{}.weight_decay;
  double val = TrainDef{}.validation_fraction;
  double dropout = 0.1;
  std::size_t shuffle_buffer = TrainDef{}.shuffle_buffer;
  std::uint64_t seed = 1;
  int threads = 0;
  int every = 1;
  int first_step = 0;  // TrainingSampleDef::first_step
  std::string schedule = TrainDef{}.schedule;
  double contact_weight = 0.0;
  bool residual = false;     // train on λ* − λ_prev (LabelKind::Residual, labels.hpp)
  double label_scale = 0.0;  // asinh compression of the labels (LabelDef::scale)
  double deadzone = 0.0;     // LabelDef::deadzone [N] (residual models)
  bool resume = false;
  bool force = false;
  bool no_plot = false;
  PgsTrainOptions pgs;  // --loss pgs-* (train_through_pgs.hpp)
};

/// The sample selection and label definition the options ask for.
TrainingSampleDef sample_def(const TrainArgs& a) {
  TrainingSampleDef d;
  d.every = a.every;
  d.first_step = a.first_step;
  d.contact_weight = a.contact_weight;
  d.labels.kind = a.residual ? LabelKind::Residual : LabelKind::Absolute;
  d.labels.scale = a.label_scale;
  d.labels.deadzone = a.deadzone;
  return d;
}

/// The options of a regression run that need no data: sample selection, dropout, and the
/// files (--resume needs OUT.ckpt; OUT is only replaced with --force).
void check_regression_options(const TrainArgs& a, const TrainingSampleDef& samples_def) {
  if (a.threads < 0) throw ConfigError("--threads must be >= 1");
  samples_def.validate();
  if (!(a.dropout >= 0 && a.dropout < 1)) throw ConfigError("--dropout must be in [0, 1)");
  const std::string ckpt = a.out + ".ckpt";
  if (a.resume && !fs::exists(ckpt))
    throw ConfigError("--resume: " + ckpt + " does not exist (nothing to resume; run without --resume)");
  if (!a.resume && fs::exists(a.out) && !a.force) throw ConfigError(a.out + " exists; use --force to replace it");
  if (!fs::exists(a.data)) throw IoError(a.data + ": no such file");
}

/// The Trainer's definition from the options; a bad one points at --help.
TrainDef regression_def(const TrainArgs& a) {
  TrainDef def;
  def.epochs = a.epochs;
  def.batch_size = a.batch;
  def.learning_rate = a.lr;
  def.momentum = a.momentum;
  def.weight_decay = a.weight_decay;
  def.validation_fraction = a.val;
  def.schedule = a.schedule;
  def.seed = a.seed;
  def.shuffle_buffer = a.shuffle_buffer;
  try {
    def.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(std::string(e.what()) + " (see deepcontact train --help)");
  }
  return def;
}

/// The data set and the samples the options select (read on demand), with the time it took
/// to open them.
struct TrainingData {
  TrainingData(const std::string& path, const TrainingSampleDef& def)
      : t0(std::chrono::steady_clock::now()),
        reader(path),
        samples(reader, def),
        seconds(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()) {}
  std::chrono::steady_clock::time_point t0;
  DataSetReader reader;
  DataSetSamples samples;
  double seconds;
};

/// What the run trains: a fresh model, or the checkpoint's with its state (--resume).
struct TrainingStart {
  ModelGrid grid;
  ArchSpec arch;
  RunIdentity id;
  std::unique_ptr<Model> model;
  std::optional<TrainState> resume;
};

TrainingStart training_start(const TrainArgs& a, const TrainingData& data, const TrainingSampleDef& samples_def,
                             const TrainDef& def, bool root) {
  // The model carries the data set's feature image and label definition, so the cnn starter
  // builds the same feature image and inverts the same labels.
  TrainingStart s{model_grid_for(data.reader, samples_def.labels),
                  select_arch(a.arch, data.reader.label_channels(), data.reader.ny(), data.reader.nx(), a.dropout),
                  {}, nullptr, std::nullopt};
  s.id = training_run_identity(data.reader, s.arch.to_toml(), def, samples_def);
  const fs::path ckpt = a.out + ".ckpt";
  if (a.resume) {
    Model loaded = load_model(ckpt);  // other version / truncated → IoError
    check_resumable(loaded, s.grid, s.arch, ckpt.string(), a.data);
    s.resume = read_train_state(H5File::open_read(ckpt.string()), s.id);
    s.model = std::make_unique<Model>(std::move(loaded));
  } else {
    s.model = std::make_unique<Model>(s.arch, s.grid, data.reader.feature_channels());
    std::error_code ec;
    if (root) fs::remove(ckpt, ec);  // a stale checkpoint of another run must not be resumed later
  }
  return s;
}

/// Rank 0's first lines: what is trained on what, and how.
void print_run_header(const TrainArgs& a, const TrainingData& data, const TrainingStart& s, const Comm& comm) {
  const int threads = a.threads > 0 ? a.threads : omp_get_max_threads();
  // --dropout only shapes the built-in architectures; an arch file states its own.
  const bool builtin_arch = is_builtin_arch(a.arch);
  char dropout_buf[32];
  std::snprintf(dropout_buf, sizeof dropout_buf, "%g", a.dropout);
  const std::string dropout_text = builtin_arch ? dropout_buf : "as in the arch file";
  std::printf("train: %zu samples (every %d of %lld) from %zu simulations of %s, %d x %d grid, %d feature channels; "
              "%zu weights (%s), %d epochs, batch %d, lr %g (%s), momentum %g, weight decay %g, dropout %s, "
              "contact weight %g, %s labels (asinh scale %g), %d thread%s, shuffle buffer %zu samples; opened in %.1f s\n",
              data.samples.size(), a.every, static_cast<long long>(data.reader.samples()),
              data.reader.simulations().size(), a.data.c_str(), s.grid.nx(), s.grid.ny(),
              data.reader.feature_channels(), s.model->network().parameter_count(), s.arch.name.c_str(), a.epochs,
              a.batch, a.lr, a.schedule.c_str(), a.momentum, a.weight_decay, dropout_text.c_str(), a.contact_weight,
              to_string(s.grid.labels.kind), a.label_scale, threads, threads == 1 ? "" : "s", a.shuffle_buffer,
              data.seconds);
  if (s.resume)
    std::printf("train: resuming after epoch %d from %s.ckpt\n", s.resume->epochs_done, a.out.c_str());
  if (comm.parallel())
    std::printf("train: data-parallel over %d ranks (each a shard of every batch of %d)\n", comm.size(), a.batch);
  std::fflush(stdout);
}

/// Rank 0's training: after every epoch the files (OUT when best, OUT.ckpt, OUT.loss.csv),
/// the progress bar and an epoch line; SIGINT (on any rank) stops after the epoch.
TrainResult train_with_checkpoints(const TrainArgs& a, Trainer& trainer, const TrainingData& data,
                                   TrainingStart& s, TrainingOutputs& files, const Comm& comm) {
  bench::ProgressBar bar("train", a.epochs);
  if (s.resume) bar.advance(s.resume->epochs_done);
  const auto on_epoch = [&](const EpochReport& e, const TrainState& st) {
    const bool improved = files.record_epoch(*s.model, e, st);
    char line[256];
    std::snprintf(line, sizeof line, "epoch %3d/%d  train %.6f  val %.6f  lr %.3g  %.1f s%s", e.epoch + 1, a.epochs,
                  e.train_loss, e.validation_loss, e.learning_rate, e.seconds, improved ? "  *best" : "");
    bar.advance(1, line);
    std::printf("%s\n", line);
    std::fflush(stdout);
    return !any_rank(comm, interrupted());
  };
  const TrainResult result =
      trainer.train(*s.model, data.samples, on_epoch, s.resume ? &*s.resume : nullptr, [] { return !interrupted(); });
  bar.finish();
  return result;
}

/// OUT.loss.png from OUT.loss.csv (bench/plots/loss_curve.py), drawn into OUT.loss.png.tmp.png
/// and renamed onto OUT.loss.png when complete; a failure only warns (and leaves no temporary).
void plot_loss_curve(const std::string& out) {
  const std::string script = data_path("bench/plots/loss_curve.py").string();
  const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string png = out + ".loss.png", tmp = png + ".tmp.png";
  const std::string cmd = py + " '" + script + "' '" + out + ".loss.csv' '" + tmp + "' >/dev/null 2>&1";
  std::string failure;
  if (std::system(cmd.c_str()) != 0 || !fs::exists(tmp)) {
    failure = cmd;
  } else {
    try {
      sync_path(tmp);
      durable_rename(tmp, png);
    } catch (const IoError& e) {
      failure = e.what();
    }
  }
  if (failure.empty()) return;
  std::error_code ignored;
  fs::remove(tmp, ignored);
  std::fprintf(stderr, "deepcontact train: warning: the loss-curve plot failed (%s)\n", failure.c_str());
}

/// The finished run: final files, the plot, and the best model in plain (unweighted)
/// standardised MSE, the unit of the theses' 0.005–0.006, whatever --contact-weight was.
void report_finished_run(const TrainArgs& a, const TrainResult& result, const TrainingData& data,
                         TrainingOutputs& files) {
  files.finish(result.history);
  if (!a.no_plot) plot_loss_curve(a.out);
  if (files.best_epoch() < 0) throw ConfigError("training diverged (loss is not finite); try a smaller --lr");
  Model best_model = load_model(a.out);
  const double tr = standardised_mse(best_model, data.samples, result.validation_simulations, false);
  const double va = standardised_mse(best_model, data.samples, result.validation_simulations, true);
  double total_s = 0;
  for (const EpochReport& e : result.history) total_s += e.seconds;
  files.remove_checkpoint();  // finished: nothing left to resume
  std::printf("train: best epoch %d of %d (%s loss %.6f); plain standardised MSE of the best model: train %.6f, "
              "validation %.6f (%zu validation simulations); %.1f s of training -> %s (%s.loss.csv, %s.loss.png)\n",
              files.best_epoch() + 1, a.epochs, std::isnan(result.history.back().validation_loss) ? "train" : "validation",
              files.best_score(),
              tr, va, result.validation_simulations.size(), total_s, a.out.c_str(), a.out.c_str(), a.out.c_str());
}

/// Regression training (MSE on the label grids), across MPI ranks when there are several
/// (mpi_train.hpp): every rank trains on a shard of every batch; rank 0 alone writes and prints.
void run_regression(const TrainArgs& a) {
  const TrainingSampleDef samples_def = sample_def(a);
  check_regression_options(a, samples_def);
  const TrainDef def = regression_def(a);
  const Comm& comm = world();
  const bool root = comm.is_root();
  if (a.threads > 0) omp_set_num_threads(a.threads);

  const TrainingData data(a.data, samples_def);
  TrainingStart start = training_start(a, data, samples_def, def, root);
  if (root) print_run_header(a, data, start, comm);

  const SigintGuard sigint;
  Trainer trainer(def);
  const CommGroup group(comm);
  trainer.set_data_parallel(&group);
  if (!root) {  // train in step with rank 0 (same weights, same stop decisions), write nothing
    const auto on_epoch = [&](const EpochReport&, const TrainState&) { return !any_rank(comm, interrupted()); };
    (void)trainer.train(*start.model, data.samples, on_epoch, start.resume ? &*start.resume : nullptr,
                        [] { return !interrupted(); });
    require_identical_weights(comm, *start.model);
    return;
  }
  // OUT (best so far; a resumed run's OUT already holds it), OUT.ckpt, OUT.loss.csv.
  TrainingOutputs files(a.out, start.id, a.data, start.resume ? &*start.resume : nullptr);
  const TrainResult result = train_with_checkpoints(a, trainer, data, start, files, comm);
  require_identical_weights(comm, *start.model);

  const int done = static_cast<int>(result.history.size());
  if (done < a.epochs) {
    std::fprintf(stderr,
                 "deepcontact: interrupted by %s: %d of %d epochs are saved in %s.ckpt (best model in %s); run the same "
                 "command with --resume to continue\n",
                 interrupt_signal_name(), done, a.epochs, a.out.c_str(), a.out.c_str());
    exit_status() = interrupt_exit_status();
    return;
  }
  report_finished_run(a, result, data, files);
}

void run(const TrainArgs& a) {
  if (a.data.empty()) throw ConfigError("--data is required");
  if (a.out.empty()) throw ConfigError("--out is required");
  check_output_file(a.out);  // before the data set is read: OUT, OUT.ckpt and OUT.loss.csv live there
  check_output_extension("--out", a.out, kHdf5Extensions, "an HDF5 model file");
  // OUT.lock keeps a second train (or a resume) off the same OUT, OUT.ckpt and OUT.loss.csv
  // whatever HDF5_USE_FILE_LOCKING says; only rank 0 writes them.
  std::optional<OutputLock> lock;
  if (world().is_root()) lock.emplace(a.out);
  if (a.pgs.gain && a.pgs.loss == "regression")
    throw ConfigError("--gain needs --loss pgs-residual, pgs-distance or pgs-field (a gain model has no label grid to regress on)");
  if (a.pgs.loss != "regression") {
    run_train_through_pgs(a.pgs, {a.data, a.out, a.epochs, a.batch, a.threads, a.every, a.first_step, a.lr, a.momentum,
                                  a.weight_decay, a.val, a.deadzone, a.seed, a.force});
    return;
  }
  run_regression(a);
}

}  // namespace

void add_train_command(CLI::App& app) {
  auto args = std::make_shared<TrainArgs>();
  auto* cmd = app.add_subcommand(
      "train", "Train the CNN on a data set from 'deepcontact generate' (docs/learning.md 'Training'): best model "
               "to OUT, checkpoint to OUT.ckpt, losses to OUT.loss.csv/.png");
  cmd->add_option("--data", args->data, "Data set (HDF5) written by deepcontact generate")->required();
  cmd->add_option("--out", args->out, "Model file to write (the best validation epoch)")->required();
  cmd->add_option("--arch", args->arch,
                  "Architecture: default (the small U-Net), seed-dense (the seed's 61 M-weight dense head) or a "
                  "TOML file (docs/learning.md)")
      ->capture_default_str();
  cmd->add_option("--epochs", args->epochs, "Epochs")->capture_default_str();
  cmd->add_option("--batch", args->batch, "Minibatch size (the seed used 200)")->capture_default_str();
  cmd->add_option("--lr", args->lr, "SGD learning rate")->capture_default_str();
  cmd->add_option("--momentum", args->momentum, "SGD momentum in [0, 1)")->capture_default_str();
  cmd->add_option("--weight-decay", args->weight_decay, "L2 weight decay (weights, not biases)")->capture_default_str();
  cmd->add_option("--val", args->val, "Validation fraction of the SIMULATIONS (not of the frames)")->capture_default_str();
  cmd->add_option("--dropout", args->dropout, "Dropout rate of the default/seed-dense architectures")
      ->capture_default_str();
  cmd->add_option("--shuffle-buffer", args->shuffle_buffer,
                  "Training samples held in memory at most (each ~104 KB at the default grid and channels). A "
                  "training split that fits is visited in a full random permutation; a larger one streams from disk "
                  "through a shuffle buffer of this size (docs/learning.md 'Training')")
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Seed of the split, initial weights, shuffles and dropout")->capture_default_str();
  cmd->add_option("--threads", args->threads, "OpenMP threads (default: OMP_NUM_THREADS or all cores)");
  cmd->add_option("--every", args->every,
                  "Use every K-th sample of each simulation (consecutive steps are nearly identical)")
      ->capture_default_str();
  cmd->add_option("--first-step", args->first_step,
                  "Use only samples of steps >= K of each simulation (a family's bench window, e.g. 195 for impact)")
      ->capture_default_str();
  cmd->add_option("--schedule", args->schedule, "Learning-rate schedule: constant, step or cosine")->capture_default_str();
  cmd->add_option("--contact-weight", args->contact_weight,
                  "Loss weight 1 + W at nodes with contact density > 0 (needs the contact_density channel)")
      ->capture_default_str();
  cmd->add_flag("--residual", args->residual,
               "Learn the correction lambda* - lambda_prev of the builtin warm start (needs the lambda_prev_n, "
               "lambda_prev_t feature channels; docs/learning.md)");
  cmd->add_option("--label-scale", args->label_scale,
                  "Learn asinh(label / S) instead of the label (0 = off): small forces keep their precision next "
                  "to impacts; the model stores S and inverts it")
      ->capture_default_str();
  cmd->add_option("--deadzone", args->deadzone,
                  "Residual models: soft threshold [N] on the predicted correction (stored in the model; "
                  "corrections within the network's noise leave builtin alone)")
      ->capture_default_str();
  cmd->add_flag("--resume", args->resume, "Continue an interrupted run from OUT.ckpt (same data and options)");
  cmd->add_flag("--force", args->force, "Replace an existing OUT");
  cmd->add_flag("--no-plot", args->no_plot, "Skip the loss-curve PNG");
  add_pgs_train_options(cmd, args->pgs);
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
