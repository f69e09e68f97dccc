#pragma once
// Trainer: minibatch SGD over an in-memory data set.
//
// Per run:  split the samples by simulation id into training and validation (so correlated
// frames of one simulation never straddle the split, DESIGN §4), compute the channel
// standardisation from the training split only, (re)initialise the weights, then for each
// epoch shuffle the training samples (Fisher–Yates with dc::Rng), run minibatches of
// forward → weighted MSE (in standardised label units) → backward → optimiser step, and
// evaluate the validation loss in inference mode.
//
// Determinism: one dc::Rng seeded from TrainDef::seed drives the split, the initial
// weights, the shuffles and the dropout masks, in that order; all reductions have a fixed
// order for a fixed OpenMP thread count. Two runs with the same seed and thread count give
// bit-identical weights and loss histories.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "dc/learning/model.hpp"

namespace dc {

/// One training example: [1, C_in, ny, nx] features, [1, C_out, ny, nx] labels, optional
/// loss weights [1, C_out or 1, ny, nx] (empty = all ones), and the simulation it came from.
struct TrainingSample {
  Tensor features;
  Tensor labels;
  Tensor weights;
  int simulation = 0;
};

/// Defaults are the seed's hyper-parameters where it had them (lr 5e-3, validation 0.2).
struct TrainDef {
  int epochs = 100;
  int batch_size = 32;                 ///< the seed used 200; 32 trains faster per epoch on 2 cores
  double learning_rate = 5e-3;
  std::string schedule = "constant";   ///< constant | step | cosine (lr_schedule.hpp)
  double momentum = 0.9;
  double weight_decay = 1e-4;          ///< L2 on weights (not biases)
  double validation_fraction = 0.2;    ///< of the simulations (not of the frames)
  std::string init = "he_normal";      ///< he_normal | glorot_uniform
  bool initialize = true;              ///< false: continue from the model's current weights
  std::uint64_t seed = 1;
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

class Trainer {
 public:
  explicit Trainer(TrainDef def);
  /// Called after every epoch (progress bar, checkpoint); return false to stop early.
  using Callback = std::function<bool(const EpochReport&)>;
  /// Train `model` in place (weights and input/output statistics). Throws InvalidArgument
  /// if the data set is empty or a sample's shapes do not fit the model.
  TrainResult train(Model& model, std::span<const TrainingSample> data, const Callback& on_epoch = {});

  /// Simulation ids for validation: ⌊f·S + ½⌋ of the S distinct ids (at least 1 when f > 0
  /// and S ≥ 2, at most S − 1), drawn with rng. Returned sorted.
  static std::vector<int> pick_validation_simulations(std::span<const TrainingSample> data, double fraction,
                                                      Rng& rng);

 private:
  TrainDef def_;
};

}  // namespace dc
