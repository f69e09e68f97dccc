#pragma once
// From a data set to training examples and back to a figure (`deepcontact train`,
// docs/learning.md "Training"): which samples are used, what their targets are (the
// model's label definition, labels.hpp), the loss weights, the model grid that records it,
// the plain standardised MSE reported for the best model, and the loss-history CSV.
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "dc/cnn/data_set.hpp"
#include "dc/learning/labels.hpp"
#include "dc/learning/model.hpp"
#include "dc/learning/trainer.hpp"

namespace dc {

/// Which samples of a data set are trained on, and their targets and weights.
struct TrainingSampleDef {
  int every = 1;              ///< every K-th sample of each simulation (consecutive steps are nearly identical)
  /// Only samples of steps ≥ first_step (0-based) of each simulation: a family whose bench
  /// window starts late (impact: the strike at ~step 217) trains on its window, not on the
  /// settling that precedes it. every counts from the first kept sample.
  int first_step = 0;
  /// W ≥ 0: loss weight map 1 + W·[contact_density > 0] (one channel shared by λ_n and λ_t;
  /// needs the contact_density feature channel). 0 = unweighted.
  double contact_weight = 0.0;
  LabelDef labels;            ///< the targets: training_labels(label, features, channels, labels)
  /// ConfigError naming the option (--every, --contact-weight, --deadzone, --label-scale).
  void validate() const;
};

/// The training examples of every completed simulation of `data`: every `def.every`-th
/// sample, labels turned into targets by training_labels, the contact weight map when
/// asked, all in memory (DataSetSamples, data_set_samples.hpp, reads them on demand instead).
/// ConfigError (naming the file) when a needed channel is missing or there is no sample at all.
std::vector<TrainingSample> load_training_samples(const DataSetReader& data, const TrainingSampleDef& def);

/// The grid of a model trained on `data` with label definition `labels`: the data set's
/// feature image and label channel names.
ModelGrid model_grid_for(const DataSetReader& data, const LabelDef& labels);

/// Plain (unweighted) MSE in standardised label units of `model` over the samples whose
/// simulation is (`in` = true) or is not (`in` = false) in the sorted list `simulations`;
/// NaN when there is none. The unit of the theses' 0.005–0.006, whatever the loss weights.
double standardised_mse(Model& model, std::span<const TrainingSample> data, const std::vector<int>& simulations,
                        bool in);
/// As above, reading the samples from `data` 32 at a time in data order.
double standardised_mse(Model& model, const SampleSource& data, const std::vector<int>& simulations, bool in);

/// The comparison value of an epoch for "best model": validation loss, or training loss
/// when there is no validation split.
double epoch_score(const EpochReport& e);

/// "epoch,train_loss,validation_loss,learning_rate,seconds" and one row per epoch (1-based).
std::string loss_csv(const std::vector<EpochReport>& history);

}  // namespace dc
