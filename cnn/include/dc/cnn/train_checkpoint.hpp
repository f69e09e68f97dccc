#pragma once
// The files of a training run (`deepcontact train`, docs/learning.md "Training"): OUT, the
// best model with its /training provenance, and the checkpoint OUT.ckpt, a model file
// (model_file.hpp) holding the latest weights plus the group /train_state (epochs_done, the
// run's random stream, validation simulations, loss history, momentum buffers; layout in
// docs/learning.md "Training checkpoints"). A run resumes only from a checkpoint of the same
// run identity (same data, architecture and every result-changing option; not the thread
// count). With the same threads the resumed run is bit-identical to an uninterrupted one.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "dc/cnn/data_set.hpp"
#include "dc/cnn/training_data.hpp"
#include "dc/io/h5.hpp"
#include "dc/learning/model.hpp"
#include "dc/learning/trainer.hpp"

namespace dc {

/// Key/value texts that fix a training run's result, in a fixed order (also written as the
/// /training provenance attributes of the trained model).
using RunIdentity = std::vector<std::pair<std::string, std::string>>;

/// The identity of a run on `data` with architecture text `arch_toml`: data_simulations,
/// data_samples, data_seed, data_grid, data_channels, arch (FNV-1a hash of the text), epochs,
/// batch, lr, momentum, weight_decay, val, seed, every, schedule, contact_weight, residual,
/// label_scale, deadzone, shuffle_buffer. Numbers as %.17g.
RunIdentity training_run_identity(const DataSetReader& data, const std::string& arch_toml, const TrainDef& train,
                                  const TrainingSampleDef& samples);

/// Writes /train_state (see the file comment) into `file`, usually from save_model's `extra`.
void write_train_state(H5File& file, const TrainState& state, const RunIdentity& id);

/// Reads /train_state. IoError when the file has none; ConfigError naming the first key of
/// `id` whose stored value differs ("--resume: F was made with K = A, this run has B …").
TrainState read_train_state(const H5File& file, const RunIdentity& id);

/// ConfigError unless `checkpoint` (a model loaded from `path`) was built for the same
/// feature image, label definition (kind, scale) and architecture as this run's `grid` and
/// `arch` (`data` names the data set in the message).
void check_resumable(Model& checkpoint, const ModelGrid& grid, const ArchSpec& arch, const std::string& path,
                     const std::string& data);

/// Saves the trained `model` (the best epoch `e` so far) to `path` atomically, with the
/// provenance group /training: the run identity's keys, data (the data set's path), epoch
/// (1-based), train_loss, validation_loss.
void save_trained_model(Model& model, const std::filesystem::path& path, const RunIdentity& id,
                        const std::string& data, const EpochReport& e);

/// Saves `model` and its state to `path` atomically (save_model + write_train_state).
void save_checkpoint(Model& model, const std::filesystem::path& path, const TrainState& state, const RunIdentity& id);

/// The files a training run keeps up to date after every epoch, in this order: OUT (the best
/// model so far, save_trained_model; only when the epoch improves on it), OUT.ckpt (the
/// latest state, save_checkpoint) and OUT.loss.csv. A kill between two writes redoes the
/// epoch, which saves the same model again; every write is atomic (tmp + rename).
class TrainingOutputs {
 public:
  /// `resumed`: the state a resumed run starts from (its history fixes the best so far,
  /// which OUT already holds), or nullptr.
  TrainingOutputs(std::filesystem::path out, RunIdentity id, std::string data, const TrainState* resumed);
  /// Writes the files for epoch `e` with state `state`; true when `e` is the new best
  /// (epoch_score strictly lower).
  bool record_epoch(Model& model, const EpochReport& e, const TrainState& state);
  /// The run completed: the final loss CSV.
  void finish(const std::vector<EpochReport>& history);
  /// Removes OUT.ckpt (the run is complete and reported: nothing left to resume).
  void remove_checkpoint();

  [[nodiscard]] const std::filesystem::path& model_path() const { return out_; }
  [[nodiscard]] const std::filesystem::path& checkpoint_path() const { return checkpoint_; }
  [[nodiscard]] std::filesystem::path loss_csv_path() const { return out_.string() + ".loss.csv"; }
  [[nodiscard]] double best_score() const { return best_; }  ///< +inf before the first epoch
  [[nodiscard]] int best_epoch() const { return best_epoch_; }  ///< 0-based; −1: none (diverged)

 private:
  std::filesystem::path out_, checkpoint_;
  RunIdentity id_;
  std::string data_;
  double best_;
  int best_epoch_ = -1;
};

}  // namespace dc
