#pragma once
// A run of `deepcontact train --loss pgs-*` (docs/learning.md "Training through PGS"):
//   1. open the data set, load --init and rebuild it on the data set's grid with its dead zone
//      (for --gain from a residual model, the output layer zeroed so training starts at builtin);
//   2. replay the simulations for each kept step's LCP (pgs_samples.hpp);
//   3. evaluate --init's validation objective (the reference to beat);
//   4. train through k unrolled sweeps (pgs_trainer.hpp), writing after every epoch OUT.loss.csv
//      (epoch,train_objective,validation_objective,validation_improved,seconds) and, when the
//      epoch's score is the best so far, OUT — both atomically, so a kill leaves the last
//      finished epoch on disk.
// The caller sees the run through hooks; nothing here prints or handles signals.
#include <cstddef>
#include <functional>
#include <string>

#include "dc/research/pgs_trainer.hpp"

namespace dc {

struct PgsTrainingRunDef {
  std::string data;         ///< the data set (deepcontact generate) whose simulations are replayed
  std::string init;         ///< the residual (or, with gain, gain) model to start from; required
  std::string out;          ///< the model file (best epoch); OUT.loss.csv next to it
  PgsTrainDef train;        ///< loss, unroll, epochs, batch, learning rate, … (pgs_trainer.hpp)
  int every = 1;            ///< keep every k-th step (≥ 1)
  int first_step = 0;       ///< first step kept (≥ 0; checked by collect_pgs_samples)
  double deadzone = 0;      ///< [N] dead zone stored in the trained model (≥ 0)
  bool gain = false;        ///< train a gain model (from a residual --init, or continue a gain one)
  bool force = false;       ///< replace an existing OUT
  /// ConfigError naming the train option (the fields only; run_pgs_training checks the files).
  void validate() const;
};

/// After the replay (step 2).
struct PgsReplayReport {
  std::size_t simulations = 0;  ///< replayed simulations
  std::size_t samples = 0;      ///< kept samples
  double seconds = 0;           ///< wall time of the replay
};

/// The --init model on the validation samples (step 3).
struct PgsInitReport {
  double objective = 0;       ///< mean J (0 = builtin)
  double better_share = 0;    ///< share of validation steps with J < 0
};

struct PgsTrainingHooks {
  /// Polled during the replay and between minibatches; false stops the run (default: never).
  std::function<bool()> keep_going;
  /// Before the replay, the long part (the data set is open and --init prepared): a CLI
  /// installs its interrupt handling here so that loading stays interruptible as usual.
  std::function<void()> on_replay_start;
  std::function<void(const PgsReplayReport&)> on_replayed;
  std::function<void(const PgsInitReport&)> on_init;
  /// After each epoch, once its files are written; `improved`: OUT now holds this epoch.
  std::function<void(const PgsEpochReport&, bool improved)> on_epoch;
};

struct PgsTrainingOutcome {
  bool replay_interrupted = false;  ///< keep_going stopped the replay: nothing was written
  std::size_t epochs = 0;           ///< finished epochs
  int best_epoch = -1;              ///< the epoch OUT holds (0-based)
  double best = 0;                  ///< its score
  double init_objective = 0;        ///< the --init model's validation objective (step 3)
  double seconds = 0;               ///< training time, summed over the finished epochs
  /// OUT is worse than --init on the validation steps: no trained epoch beat where it started.
  [[nodiscard]] bool worse_than_init() const { return best > init_objective; }
};

/// The run of `def` (validated). IoError when the data set is missing; ConfigError when OUT
/// exists without force, --init does not fit the data set (kernel, spacing, support, feature
/// channels, a grid-dependent parameter), a gain --init is continued without gain, or no
/// epoch finished.
PgsTrainingOutcome run_pgs_training(const PgsTrainingRunDef& def, const PgsTrainingHooks& hooks = {});

}  // namespace dc
