// The training checkpoint's /train_state and the run identity (train_checkpoint.hpp).
#include "dc/cnn/train_checkpoint.hpp"

#include "dc/io/atomic_file.hpp"

#include <cstdio>
#include <limits>

#include "dc/core/error.hpp"
#include "dc/learning/model_file.hpp"

namespace dc {

namespace {
constexpr const char* kState = "/train_state";

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
}  // namespace

RunIdentity training_run_identity(const DataSetReader& r, const std::string& arch_toml, const TrainDef& t,
                                  const TrainingSampleDef& s) {
  std::uint64_t arch_hash = 1469598103934665603ULL;  // FNV-1a of the arch text
  for (unsigned char c : arch_toml) arch_hash = (arch_hash ^ c) * 1099511628211ULL;
  std::string names;
  for (const auto& n : r.feature_channel_names()) names += (names.empty() ? "" : ",") + n;
  RunIdentity id{{"data_simulations", std::to_string(r.simulations().size())},
          {"data_samples", std::to_string(r.samples())},
          {"data_seed", std::to_string(r.params().seed)},
          {"data_grid", std::to_string(r.nx()) + "x" + std::to_string(r.ny())},
          {"data_channels", names},
          {"arch", std::to_string(arch_hash)},
          {"epochs", std::to_string(t.epochs)},
          {"batch", std::to_string(t.batch_size)},
          {"lr", num(t.learning_rate)},
          {"momentum", num(t.momentum)},
          {"weight_decay", num(t.weight_decay)},
          {"val", num(t.validation_fraction)},
          {"seed", std::to_string(t.seed)},
          {"every", std::to_string(s.every)},
          {"schedule", t.schedule},
          {"contact_weight", num(s.contact_weight)},
          {"residual", s.labels.kind == LabelKind::Residual ? "1" : "0"},
          {"label_scale", num(s.labels.scale)},
          {"deadzone", num(s.labels.deadzone)},
          // The buffer fixes the visiting order of a training split larger than it.
          {"shuffle_buffer", std::to_string(t.shuffle_buffer)}};
  // Only when set, so checkpoints without a first_step key stay resumable.
  if (s.first_step > 0) id.emplace_back("first_step", std::to_string(s.first_step));
  return id;
}

void write_train_state(H5File& f, const TrainState& st, const RunIdentity& id) {
  f.create_group(kState);
  f.set_attribute<std::int32_t>(kState, "epochs_done", st.epochs_done);
  f.set_attribute(kState, "rng_type", st.rng_type);
  for (const auto& [k, v] : id) f.set_attribute(kState, "run_" + k, v);
  f.write<std::uint8_t>("/train_state/rng_state", st.rng_state, {st.rng_state.size()});
  std::vector<std::int32_t> val(st.validation_simulations.begin(), st.validation_simulations.end());
  f.write<std::int32_t>("/train_state/validation_simulations", val, {val.size()});
  std::vector<double> hist;  // epoch rows: train, validation, lr, seconds
  for (const EpochReport& e : st.history)
    hist.insert(hist.end(), {e.train_loss, e.validation_loss, e.learning_rate, e.seconds});
  f.write<double>("/train_state/history", hist, {st.history.size(), 4});
  f.set_attribute<std::int32_t>(kState, "momentum_buffers", static_cast<std::int32_t>(st.velocity.size()));
  for (std::size_t i = 0; i < st.velocity.size(); ++i)
    f.write<float>("/train_state/momentum/" + std::to_string(i), st.velocity[i], {st.velocity[i].size()});
}

TrainState read_train_state(const H5File& f, const RunIdentity& id) {
  const std::string& file = f.path();
  if (!f.is_group(kState)) throw IoError(file + ": not a training checkpoint (no /train_state)");
  for (const auto& [k, v] : id) {
    const std::string name = "run_" + k;
    const std::string stored = f.has_attribute(kState, name) ? f.attribute_string(kState, name) : "?";
    if (stored != v)
      throw ConfigError("--resume: " + file + " was made with " + k + " = " + stored + ", this run has " + v +
                        " (use the same data and options, or start afresh without --resume)");
  }
  TrainState st;
  st.epochs_done = f.attribute<std::int32_t>(kState, "epochs_done");
  st.rng_type = f.attribute_string(kState, "rng_type");
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
  const int buffers = f.attribute<std::int32_t>(kState, "momentum_buffers");
  for (int i = 0; i < buffers; ++i) st.velocity.push_back(f.read<float>("/train_state/momentum/" + std::to_string(i)));
  return st;
}

void check_resumable(Model& checkpoint, const ModelGrid& grid, const ArchSpec& arch, const std::string& path,
                     const std::string& data) {
  const ModelGrid& g = checkpoint.grid();
  const auto& a = g.image.sph;
  const auto& b = grid.image.sph;
  if (g.nx() != grid.nx() || g.ny() != grid.ny() || g.image.channels != grid.image.channels ||
      g.label_channels != grid.label_channels || g.labels.kind != grid.labels.kind ||
      g.labels.scale != grid.labels.scale || a.grid.spacing != b.grid.spacing || a.support != b.support ||
      a.kernel != b.kernel)
    throw ConfigError("--resume: " + path + " holds a model for another grid or channel set than " + data);
  if (checkpoint.network().arch().to_toml() != arch.to_toml())
    throw ConfigError("--resume: " + path + " holds another architecture than --arch selects");
}

void save_trained_model(Model& model, const std::filesystem::path& path, const RunIdentity& id,
                        const std::string& data, const EpochReport& e) {
  save_model(model, path, [&](H5File& f) {
    f.create_group("/training");
    for (const auto& [k, v] : id) f.set_attribute("/training", k, v);
    f.set_attribute("/training", "data", data);
    f.set_attribute<std::int32_t>("/training", "epoch", e.epoch + 1);
    f.set_attribute<double>("/training", "train_loss", e.train_loss);
    f.set_attribute<double>("/training", "validation_loss", e.validation_loss);
  });
}

void save_checkpoint(Model& model, const std::filesystem::path& path, const TrainState& state, const RunIdentity& id) {
  save_model(model, path, [&](H5File& f) { write_train_state(f, state, id); });
}

TrainingOutputs::TrainingOutputs(std::filesystem::path out, RunIdentity id, std::string data, const TrainState* resumed)
    : out_(std::move(out)),
      checkpoint_(out_.string() + ".ckpt"),
      id_(std::move(id)),
      data_(std::move(data)),
      best_(std::numeric_limits<double>::infinity()) {
  if (resumed)
    for (const EpochReport& e : resumed->history)
      if (epoch_score(e) < best_) best_ = epoch_score(e), best_epoch_ = e.epoch;
}

bool TrainingOutputs::record_epoch(Model& model, const EpochReport& e, const TrainState& state) {
  const bool improved = epoch_score(e) < best_;
  if (improved) {
    best_ = epoch_score(e);
    best_epoch_ = e.epoch;
    save_trained_model(model, out_, id_, data_, e);
  }
  save_checkpoint(model, checkpoint_, state, id_);
  write_file_atomically(loss_csv_path().string(), loss_csv(state.history));
  return improved;
}

void TrainingOutputs::finish(const std::vector<EpochReport>& history) {
  write_file_atomically(loss_csv_path().string(), loss_csv(history));
}

void TrainingOutputs::remove_checkpoint() {
  std::error_code ec;
  std::filesystem::remove(checkpoint_, ec);
}

}  // namespace dc
