// deepcontact train: fit the CNN (dc_learning) to a data set written by `deepcontact generate`
// (issue 4; docs/learning.md "Training").
//
//   data set ──(every K-th sample of each simulation)──▶ samples ──split by simulation──▶
//   train / validation ──▶ Trainer (SGD, standardisation from the training split) ──▶
//   OUT (best validation loss so far), OUT.ckpt (latest state), OUT.loss.csv, OUT.loss.png
//
// Crash safety: after every epoch the best model is written to OUT and the latest state
// (weights + random stream + momentum + history) to OUT.ckpt, both atomically (write
// .tmp, rename), so a kill at any moment leaves the last finished epoch on disk. `--resume`
// reloads OUT.ckpt, checks that it belongs to the same data and options, and continues
// with the next epoch; with the same --threads the result is bit-identical to an
// uninterrupted run. SIGINT sets a flag (the handler does nothing else) that the trainer
// polls between minibatches; the unfinished epoch is dropped and the command exits 130.
#include <CLI/CLI.hpp>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "sigint_guard.hpp"
#include "dc/engine/error.hpp"
#include "dc/io/atomic_file.hpp"
#include "dc/io/h5.hpp"
#include "dc/learning/arch.hpp"
#include "dc/learning/data_set.hpp"
#include "dc/learning/model_file.hpp"
#include "dc/learning/mse_loss.hpp"
#include "dc/learning/trainer.hpp"
#include "dc/warmstart/sph_kernel.hpp"
#include "progress_bar.hpp"

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
  std::uint64_t seed = 1;
  int threads = 0;
  int every = 1;
  std::string schedule = TrainDef{}.schedule;
  double contact_weight = 0.0;
  bool residual = false;  // train on λ* − λ_prev (ModelGrid::label_kind = "residual")
  double label_scale = 0.0;  // asinh compression of the labels (ModelGrid::label_scale)
  double deadzone = 0.0;     // ModelGrid::correction_deadzone [N] (residual models)
  bool resume = false;
  bool force = false;
  bool no_plot = false;
};

/// The options and data that fix a training run's result (not --threads, which only
/// changes the last bits). Stored in the checkpoint; --resume requires equality, key by key.
std::vector<std::pair<std::string, std::string>> run_identity(const TrainArgs& a, const DataSetReader& r,
                                                              const std::string& arch_text) {
  const auto num = [](double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return std::string(buf);
  };
  std::uint64_t arch_hash = 1469598103934665603ULL;  // FNV-1a of the arch text
  for (unsigned char c : arch_text) arch_hash = (arch_hash ^ c) * 1099511628211ULL;
  std::string names;
  for (const auto& n : r.feature_channel_names()) names += (names.empty() ? "" : ",") + n;
  return {{"data_simulations", std::to_string(r.simulations().size())},
          {"data_samples", std::to_string(r.samples())},
          {"data_seed", std::to_string(r.params().seed)},
          {"data_grid", std::to_string(r.nx()) + "x" + std::to_string(r.ny())},
          {"data_channels", names},
          {"arch", std::to_string(arch_hash)},
          {"epochs", std::to_string(a.epochs)},
          {"batch", std::to_string(a.batch)},
          {"lr", num(a.lr)},
          {"momentum", num(a.momentum)},
          {"weight_decay", num(a.weight_decay)},
          {"val", num(a.val)},
          {"seed", std::to_string(a.seed)},
          {"every", std::to_string(a.every)},
          {"schedule", a.schedule},
          {"contact_weight", num(a.contact_weight)},
          {"residual", a.residual ? "1" : "0"},
          {"label_scale", num(a.label_scale)},
          {"deadzone", num(a.deadzone)}};
}

ArchSpec select_arch(const TrainArgs& a, int label_channels, int ny, int nx) {
  if (a.arch.empty() || a.arch == "default") return default_arch(label_channels, a.dropout);
  if (a.arch == "seed-dense") return seed_dense_arch(label_channels, ny, nx, a.dropout);
  if (!fs::exists(a.arch))
    throw ConfigError("--arch '" + a.arch + "': not 'default', 'seed-dense' or an existing TOML file");
  return ArchSpec::load(a.arch);
}

/// Every `every`-th sample of every completed simulation, with the optional contact weight
/// map 1 + W·[contact_density > 0] (one channel, shared by λ_n and λ_t). `residual`: the
/// labels become label − (lambda_prev_n, lambda_prev_t) feature channels, the splat of
/// λ* − λ_prev (feature_image.hpp).
std::vector<TrainingSample> load_samples(const DataSetReader& r, int every, double contact_weight, bool residual,
                                         double label_scale) {
  const auto& names = r.feature_channel_names();
  const auto channel = [&](const char* name) {
    const auto it = std::find(names.begin(), names.end(), name);
    return it == names.end() ? -1 : static_cast<int>(it - names.begin());
  };
  const int density = channel("contact_density");
  if (contact_weight > 0 && density < 0)
    throw ConfigError("--contact-weight needs a contact_density feature channel; " + r.path() + " has none");
  const int prev_n = channel("lambda_prev_n"), prev_t = channel("lambda_prev_t");
  if (residual && (prev_n < 0 || prev_t < 0))
    throw ConfigError("--residual needs the feature channels lambda_prev_n and lambda_prev_t; " + r.path() +
                      " has none (generate it with --channels including them)");
  std::vector<TrainingSample> out;
  for (const DataSetSimulation& sim : r.simulations()) {
    std::vector<std::int64_t> rows;
    for (std::int64_t k = 0; k < sim.samples; k += every) rows.push_back(sim.sample_begin + k);
    if (rows.empty()) continue;
    const Tensor f = r.features(rows), l = r.labels(rows);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      TrainingSample t;
      t.features = Tensor(1, f.c(), f.h(), f.w());
      t.labels = Tensor(1, l.c(), l.h(), l.w());
      std::memcpy(t.features.data(), f.sample(static_cast<int>(k)), f.shape().sample_count() * sizeof(float));
      std::memcpy(t.labels.data(), l.sample(static_cast<int>(k)), l.shape().sample_count() * sizeof(float));
      if (residual) {
        const std::size_t P = f.shape().plane();
        for (int c = 0; c < 2; ++c) {
          const float* prev = t.features.data() + static_cast<std::size_t>(c == 0 ? prev_n : prev_t) * P;
          float* lab = t.labels.data() + static_cast<std::size_t>(c) * P;
          for (std::size_t q = 0; q < P; ++q) lab[q] -= prev[q];
        }
      }
      compress_labels(t.labels, label_scale);
      if (contact_weight > 0) {
        t.weights = Tensor(1, 1, f.h(), f.w());
        const float* cd = t.features.data() + static_cast<std::size_t>(density) * f.shape().plane();
        for (std::size_t p = 0; p < f.shape().plane(); ++p)
          t.weights[p] = 1.0f + (cd[p] > 0.0f ? static_cast<float>(contact_weight) : 0.0f);
      }
      t.simulation = sim.index;
      out.push_back(std::move(t));
    }
  }
  if (out.empty()) throw ConfigError(r.path() + ": the data set holds no samples");
  return out;
}

/// Writes `text` to `path` atomically (tmp + rename).
void write_atomic(const fs::path& path, const std::string& text) { write_file_atomically(path.string(), text); }

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

// ---- checkpoint state (/train_state in OUT.ckpt; docs/learning.md "Training") ----------

void write_state(H5File& f, const TrainState& st, const std::vector<std::pair<std::string, std::string>>& id) {
  f.create_group("/train_state");
  f.set_attribute<std::int32_t>("/train_state", "epochs_done", st.epochs_done);
  f.set_attribute("/train_state", "rng_type", st.rng_type);
  for (const auto& [k, v] : id) f.set_attribute("/train_state", "run_" + k, v);
  f.write<std::uint8_t>("/train_state/rng_state", st.rng_state, {st.rng_state.size()});
  std::vector<std::int32_t> val(st.validation_simulations.begin(), st.validation_simulations.end());
  f.write<std::int32_t>("/train_state/validation_simulations", val, {val.size()});
  std::vector<double> hist;  // epoch rows: train, validation, lr, seconds
  for (const EpochReport& e : st.history) hist.insert(hist.end(), {e.train_loss, e.validation_loss, e.learning_rate, e.seconds});
  f.write<double>("/train_state/history", hist, {st.history.size(), 4});
  f.set_attribute<std::int32_t>("/train_state", "momentum_buffers", static_cast<std::int32_t>(st.velocity.size()));
  for (std::size_t i = 0; i < st.velocity.size(); ++i)
    f.write<float>("/train_state/momentum/" + std::to_string(i), st.velocity[i], {st.velocity[i].size()});
}

TrainState read_state(const H5File& f, const std::vector<std::pair<std::string, std::string>>& id) {
  const std::string& file = f.path();
  if (!f.is_group("/train_state")) throw IoError(file + ": not a training checkpoint (no /train_state)");
  for (const auto& [k, v] : id) {
    const std::string name = "run_" + k;
    const std::string stored = f.has_attribute("/train_state", name) ? f.attribute_string("/train_state", name) : "?";
    if (stored != v)
      throw ConfigError("--resume: " + file + " was made with " + k + " = " + stored + ", this run has " + v +
                        " (use the same data and options, or start afresh without --resume)");
  }
  TrainState st;
  st.epochs_done = f.attribute<std::int32_t>("/train_state", "epochs_done");
  st.rng_type = f.attribute_string("/train_state", "rng_type");
  st.rng_state = f.read<std::uint8_t>("/train_state/rng_state");
  for (std::int32_t v : f.read<std::int32_t>("/train_state/validation_simulations"))
    st.validation_simulations.push_back(v);
  const auto hist = f.read<double>("/train_state/history", {kH5Any, 4});
  for (std::size_t e = 0; e < hist.size() / 4; ++e) {
    EpochReport r;
    r.epoch = static_cast<int>(e);
    r.train_loss = hist[4 * e];
    r.validation_loss = hist[4 * e + 1];
    r.learning_rate = hist[4 * e + 2];
    r.seconds = hist[4 * e + 3];
    st.history.push_back(r);
  }
  const int buffers = f.attribute<std::int32_t>("/train_state", "momentum_buffers");
  for (int i = 0; i < buffers; ++i) st.velocity.push_back(f.read<float>("/train_state/momentum/" + std::to_string(i)));
  return st;
}

/// The comparison value of an epoch for "best model": validation loss, or training loss
/// when there is no validation split.
double score(const EpochReport& e) { return std::isnan(e.validation_loss) ? e.train_loss : e.validation_loss; }

/// Plain (unweighted) MSE in standardised label units of `model` over the samples whose
/// simulation is (in = true) or is not (in = false) in the sorted list `sims`; batches of
/// 32 (batch-1 inference pays a fork–join per layer per sample).
double plain_mse(Model& model, std::span<const TrainingSample> data, const std::vector<int>& sims, bool in) {
  std::vector<const TrainingSample*> picked;
  for (const TrainingSample& s : data)
    if (std::binary_search(sims.begin(), sims.end(), s.simulation) == in) picked.push_back(&s);
  if (picked.empty()) return std::numeric_limits<double>::quiet_NaN();
  const MseLoss mse;
  double sum = 0;
  Tensor x, y;
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
    compress_labels(pred, model.grid().label_scale);  // back to the network's label space
    model.output_stats.apply(pred);
    model.output_stats.apply(y);
    sum += b * mse(pred, y);
  }
  return sum / static_cast<double>(picked.size());
}

void run(const TrainArgs& a) {
  if (a.data.empty()) throw ConfigError("--data is required");
  if (a.out.empty()) throw ConfigError("--out is required");
  if (a.threads < 0) throw ConfigError("--threads must be >= 1");
  if (a.every < 1) throw ConfigError("--every must be >= 1");
  if (!(a.contact_weight >= 0) || !std::isfinite(a.contact_weight))
    throw ConfigError("--contact-weight must be a finite number >= 0");
  if (!(a.deadzone >= 0) || !std::isfinite(a.deadzone)) throw ConfigError("--deadzone must be a finite number >= 0");
  if (a.deadzone > 0 && !a.residual) throw ConfigError("--deadzone applies to residual models only (add --residual)");
  if (!(a.label_scale >= 0) || !std::isfinite(a.label_scale))
    throw ConfigError("--label-scale must be a finite number >= 0");
  if (!(a.dropout >= 0 && a.dropout < 1)) throw ConfigError("--dropout must be in [0, 1)");
  const fs::path out = a.out, ckpt = a.out + ".ckpt";
  if (a.resume && !fs::exists(ckpt))
    throw ConfigError("--resume: " + ckpt.string() + " does not exist (nothing to resume; run without --resume)");
  if (!a.resume && fs::exists(out) && !a.force) throw ConfigError(a.out + " exists; use --force to replace it");
  if (!fs::exists(a.data)) throw IoError(a.data + ": no such file");

  TrainDef def;
  def.epochs = a.epochs;
  def.batch_size = a.batch;
  def.learning_rate = a.lr;
  def.momentum = a.momentum;
  def.weight_decay = a.weight_decay;
  def.validation_fraction = a.val;
  def.schedule = a.schedule;
  def.seed = a.seed;
  try {
    def.validate();
  } catch (const ConfigError& e) {
    throw ConfigError(std::string(e.what()) + " (see deepcontact train --help)");
  }
  if (a.threads > 0) omp_set_num_threads(a.threads);
  const int threads = a.threads > 0 ? a.threads : omp_get_max_threads();

  const auto t_load = std::chrono::steady_clock::now();
  const DataSetReader reader(a.data);
  const std::vector<TrainingSample> samples = load_samples(reader, a.every, a.contact_weight, a.residual, a.label_scale);
  const double load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count();

  // The model carries the data set's grid and channel names, so the cnn starter can check
  // that it builds the same feature image.
  const DataSetParams& p = reader.params();
  ModelGrid grid;
  grid.d = p.image.sph.grid.spacing;
  grid.h = p.image.sph.support;
  grid.kernel = to_string(p.image.sph.kernel);
  grid.nx = reader.nx();
  grid.ny = reader.ny();
  grid.feature_channels = reader.feature_channel_names();
  grid.label_channels = reader.label_channel_names();
  grid.label_kind = a.residual ? "residual" : "absolute";
  grid.label_scale = a.label_scale;
  grid.correction_deadzone = a.deadzone;
  const ArchSpec arch = select_arch(a, reader.label_channels(), reader.ny(), reader.nx());
  const auto id = run_identity(a, reader, arch.to_toml());

  std::unique_ptr<Model> model;
  std::optional<TrainState> resume;
  if (a.resume) {
    Model loaded = load_model(ckpt);  // other version / truncated → IoError
    const ModelGrid& g = loaded.grid();
    if (g.nx != grid.nx || g.ny != grid.ny || g.feature_channels != grid.feature_channels ||
        g.label_channels != grid.label_channels || g.label_kind != grid.label_kind || g.label_scale != grid.label_scale || g.d != grid.d || g.h != grid.h || g.kernel != grid.kernel)
      throw ConfigError("--resume: " + ckpt.string() + " holds a model for another grid or channel set than " + a.data);
    if (loaded.network().arch().to_toml() != arch.to_toml())
      throw ConfigError("--resume: " + ckpt.string() + " holds another architecture than --arch selects");
    resume = read_state(H5File::open_read(ckpt.string()), id);
    model = std::make_unique<Model>(std::move(loaded));
  } else {
    model = std::make_unique<Model>(arch, grid, reader.feature_channels());
    std::error_code ec;
    fs::remove(ckpt, ec);  // a stale checkpoint of another run must not be resumed later
  }

  // --dropout only shapes the built-in architectures; an arch file states its own.
  const bool builtin_arch = a.arch.empty() || a.arch == "default" || a.arch == "seed-dense";
  char dropout_buf[32];
  std::snprintf(dropout_buf, sizeof dropout_buf, "%g", a.dropout);
  const std::string dropout_text = builtin_arch ? dropout_buf : "as in the arch file";
  std::printf("train: %zu samples (every %d of %lld) from %zu simulations of %s, %d x %d grid, %d feature channels; "
              "%zu weights (%s), %d epochs, batch %d, lr %g (%s), momentum %g, weight decay %g, dropout %s, "
              "contact weight %g, %s labels (asinh scale %g), %d thread%s; loaded in %.1f s\n",
              samples.size(), a.every, static_cast<long long>(reader.samples()), reader.simulations().size(),
              a.data.c_str(), grid.nx, grid.ny, reader.feature_channels(), model->network().parameter_count(),
              arch.name.c_str(), a.epochs, a.batch, a.lr, a.schedule.c_str(), a.momentum, a.weight_decay,
              dropout_text.c_str(), a.contact_weight, grid.label_kind.c_str(), a.label_scale, threads, threads == 1 ? "" : "s", load_s);
  if (resume) std::printf("train: resuming after epoch %d from %s\n", resume->epochs_done, ckpt.string().c_str());
  std::fflush(stdout);

  // Best so far (of the resumed history, if any): OUT already holds that model.
  double best = std::numeric_limits<double>::infinity();
  int best_epoch = -1;
  if (resume)
    for (const EpochReport& e : resume->history)
      if (score(e) < best) best = score(e), best_epoch = e.epoch;

  const SigintGuard sigint;
  ProgressBar bar("train", a.epochs);
  if (resume) bar.advance(resume->epochs_done);
  const auto provenance = [&](H5File& f) {
    f.create_group("/training");
    for (const auto& [k, v] : id) f.set_attribute("/training", k, v);
    f.set_attribute("/training", "data", a.data);
  };
  Trainer trainer(def);
  const auto on_epoch = [&](const EpochReport& e, const TrainState& st) {
    const bool improved = score(e) < best;
    if (improved) {
      best = score(e);
      best_epoch = e.epoch;
      save_model(*model, out, [&](H5File& f) {
        provenance(f);
        f.set_attribute<std::int32_t>("/training", "epoch", e.epoch + 1);
        f.set_attribute<double>("/training", "train_loss", e.train_loss);
        f.set_attribute<double>("/training", "validation_loss", e.validation_loss);
      });
    }
    // The checkpoint after OUT: a kill in between redoes this epoch, which saves the same
    // model again.
    save_model(*model, ckpt, [&](H5File& f) { write_state(f, st, id); });
    write_atomic(a.out + ".loss.csv", loss_csv(st.history));
    char line[256];
    std::snprintf(line, sizeof line, "epoch %3d/%d  train %.6f  val %.6f  lr %.3g  %.1f s%s", e.epoch + 1, a.epochs,
                  e.train_loss, e.validation_loss, e.learning_rate, e.seconds, improved ? "  *best" : "");
    bar.advance(1, line);
    std::printf("%s\n", line);
    std::fflush(stdout);
    return !interrupted();
  };
  const TrainResult result =
      trainer.train(*model, samples, on_epoch, resume ? &*resume : nullptr, [] { return !interrupted(); });
  bar.finish();

  const int done = static_cast<int>(result.history.size());
  if (done < a.epochs) {
    std::fprintf(stderr,
                 "deepcontact: interrupted: %d of %d epochs are saved in %s (best model in %s); run the same "
                 "command with --resume to continue\n",
                 done, a.epochs, ckpt.string().c_str(), a.out.c_str());
    exit_status() = 130;
    return;
  }
  write_atomic(a.out + ".loss.csv", loss_csv(result.history));
  if (!a.no_plot) {
    const std::string script = std::string(DC_SOURCE_DIR) + "/bench/plots/loss_curve.py";
    const std::string py = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const std::string cmd = py + " '" + script + "' '" + a.out + ".loss.csv' '" + a.out + ".loss.png' >/dev/null 2>&1";
    if (std::system(cmd.c_str()) != 0 || !fs::exists(a.out + ".loss.png"))
      std::fprintf(stderr, "deepcontact train: warning: the loss-curve plot failed (%s)\n", cmd.c_str());
  }

  if (best_epoch < 0) throw ConfigError("training diverged (loss is not finite); try a smaller --lr");
  // Report the best model in plain (unweighted) standardised MSE, the unit of the theses'
  // 0.005–0.006, whatever --contact-weight was.
  Model best_model = load_model(out);
  const double tr = plain_mse(best_model, samples, result.validation_simulations, false);
  const double va = plain_mse(best_model, samples, result.validation_simulations, true);
  double total_s = 0;
  for (const EpochReport& e : result.history) total_s += e.seconds;
  std::error_code ec;
  fs::remove(ckpt, ec);  // finished: nothing left to resume
  std::printf("train: best epoch %d of %d (%s loss %.6f); plain standardised MSE of the best model: train %.6f, "
              "validation %.6f (%zu validation simulations); %.1f s of training -> %s (%s.loss.csv, %s.loss.png)\n",
              best_epoch + 1, a.epochs, std::isnan(result.history.back().validation_loss) ? "train" : "validation", best,
              tr, va, result.validation_simulations.size(), total_s, a.out.c_str(), a.out.c_str(), a.out.c_str());
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
  cmd->add_option("--seed", args->seed, "Seed of the split, initial weights, shuffles and dropout")->capture_default_str();
  cmd->add_option("--threads", args->threads, "OpenMP threads (default: OMP_NUM_THREADS or all cores)");
  cmd->add_option("--every", args->every,
                  "Use every K-th sample of each simulation (consecutive steps are nearly identical)")
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
  cmd->callback([args] { run(*args); });
}

}  // namespace dc::cli
