#pragma once
// Trainer: minibatch SGD over a data set read a few samples at a time (sample_source.hpp).
// Per run: split the samples by simulation id into training and validation (correlated
// frames of one simulation never straddle the split, docs/design.md §4), standardise the
// channels from the training split only, (re)initialise the weights, then per epoch visit the
// training samples in shuffle_stream.hpp's order with minibatches of forward → weighted MSE (in
// standardised label units) → backward → optimiser step, and evaluate the validation loss in
// inference mode (data order). Determinism: one dc::Rng seeded from TrainDef::seed drives the
// split, the initial weights, the shuffles and the dropout masks, in that order; reductions
// have a fixed order for a fixed OpenMP thread count, so the same seed, thread count and
// shuffle buffer give bit-identical weights and losses.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "dc/learning/data_parallel.hpp"
#include "dc/learning/model.hpp"
#include "dc/learning/sample_source.hpp"

namespace dc {

/// Training hyper-parameters; the defaults are those of `deepcontact train`.
struct TrainDef {
  int epochs = 100;
  int batch_size = 32;                 ///< samples per minibatch
  double learning_rate = 5e-3;
  std::string schedule = "constant";   ///< constant | step | cosine (lr_schedule.hpp)
  double momentum = 0.9;
  double weight_decay = 1e-4;          ///< L2 on weights (not biases)
  double validation_fraction = 0.2;    ///< of the simulations (not of the frames)
  std::string init = "he_normal";      ///< he_normal | glorot_uniform
  bool initialize = true;              ///< false: continue from the model's current weights
  std::uint64_t seed = 1;
  /// Training samples held in memory at most (shuffle_stream.hpp). A training split of at most
  /// this many samples is kept whole and visited in a Fisher–Yates order; a larger
  /// one is streamed through a shuffle buffer of this size, which changes the visiting order.
  /// 2048 samples ≈ 210 MB at the default 61 × 61 grid with 5 feature and 2 label channels.
  std::size_t shuffle_buffer = 2048;
  /// Throws ConfigError naming the field for a non-positive epochs/batch/lr, a fraction
  /// outside [0, 1), or an unknown schedule/initialiser.
  void validate() const;
};

struct EpochReport {
  int epoch = 0;                 ///< 0-based
  double train_loss = 0.0;       ///< sample-weighted mean of the epoch's minibatch losses
  double validation_loss = 0.0;  ///< NaN when there is no validation split
  double learning_rate = 0.0;
  double seconds = 0.0;          ///< wall time of the epoch (training + validation)
};

struct TrainResult {
  std::vector<EpochReport> history;
  std::vector<int> train_simulations, validation_simulations;
};

/// What a training run needs besides the model's weights to continue exactly where it
/// stopped (checkpoint/resume, `deepcontact train --resume`): the epochs done, their
/// reports, the run's random stream and the SGD momentum buffers after the last finished
/// epoch. With the same data, TrainDef and thread count, a run resumed from this state
/// continues bit-identically to an uninterrupted one (the split and the standardisation
/// are recomputed: they are deterministic functions of the seed and the data).
struct TrainState {
  int epochs_done = 0;
  std::vector<EpochReport> history;
  std::string rng_type;                        ///< Rng::algorithm() ("mt19937")
  std::vector<std::uint8_t> rng_state;         ///< Rng::save_state() (GSL's state block)
  std::vector<std::vector<float>> velocity;    ///< momentum per parameter (empty: none yet)
  std::vector<int> validation_simulations;     ///< the split the state belongs to
};

class Trainer {
 public:
  explicit Trainer(TrainDef def);
  /// Called after every epoch (progress bar, checkpoint); return false to stop early.
  using Callback = std::function<bool(const EpochReport&)>;
  /// Train `model` in place (weights and input/output statistics). Throws InvalidArgument
  /// if the data set is empty or a sample's shapes do not fit the model.
  TrainResult train(Model& model, std::span<const TrainingSample> data, const Callback& on_epoch = {});

  /// Called after every epoch with the report and the state to checkpoint (valid during
  /// the call only); return false to stop.
  using StateCallback = std::function<bool(const EpochReport&, const TrainState&)>;
  /// As above; with `resume` (a state saved by an earlier run with the same data and
  /// TrainDef, and `model` holding that run's weights) it skips the initialisation,
  /// restores the random stream and the momentum, and continues at epoch
  /// resume->epochs_done; the returned history includes the resumed epochs. Throws
  /// InvalidArgument when the state does not fit (another split, parameter sizes, rng).
  /// `keep_going` (optional) is polled before every minibatch; when it returns false the
  /// unfinished epoch is abandoned (neither reported nor in the history) and train returns.
  TrainResult train(Model& model, std::span<const TrainingSample> data, const StateCallback& on_epoch,
                    const TrainState* resume, const std::function<bool()>& keep_going = {});

  /// As above over any SampleSource: the samples are read a block at a time and at most
  /// TrainDef::shuffle_buffer training samples (plus a read block and the batch buffers) are
  /// held in memory. Throws InvalidArgument if the source is empty or its shapes do not fit
  /// the model.
  TrainResult train(Model& model, const SampleSource& data, const StateCallback& on_epoch, const TrainState* resume,
                    const std::function<bool()>& keep_going = {});

  /// Simulation ids for validation: ⌊f·S + ½⌋ of the S distinct ids (at least 1 when f > 0
  /// and S ≥ 2, at most S − 1), drawn with rng. Returned sorted.
  static std::vector<int> pick_validation_simulations(std::span<const TrainingSample> data, double fraction,
                                                      Rng& rng);
  /// As above from the simulation id of every sample.
  static std::vector<int> pick_validation_simulations(std::span<const int> sample_simulations, double fraction,
                                                      Rng& rng);

  /// Data-parallel training across a process group (data_parallel.hpp); nullptr or a
  /// group of size 1 = this process alone (the default). The group must outlive train().
  void set_data_parallel(const DataParallelGroup* group) { group_ = group; }

 private:
  TrainDef def_;
  const DataParallelGroup* group_ = nullptr;
};

}  // namespace dc
